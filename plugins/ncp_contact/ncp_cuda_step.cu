/* ncp_cuda_step.cu - the constraint update of Algorithm 4 on the GPU, in
 * phases between its W products (see ncp_cuda.h for the sequence): one
 * single-block kernel a phase, or two phases with no product between them
 * (CR's F and the next E) in one (the phases' code: ncp_cuda_phases.cuh). */
#include "ncp_cuda_phases.cuh"

namespace {

/* phase, then phase2 (>= 0) after a block barrier: what two launches of
 * one phase each compute (the same block code, in the same order). */
__global__ void __launch_bounds__(kThreads)
    k_phase(int phase, int last, int phase2, int last2, const pl_ncp_cuda_rows *__restrict__ Rp,
            pl_ncp_cuda_vecs V, pl_ncp_cuda_params P)
{
    const pl_ncp_cuda_rows R = *Rp; /* the step's rows (a graph keeps only the address) */
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    run_phase<kThreads>(phase, R, V, P, last, rd);
    if (phase2 < 0) return;
    __syncthreads();
    run_phase<kThreads>(phase2, R, V, P, last2, rd);
}

} // namespace

extern "C" int ncp_cuda_phase_run(struct CUstream_st *st, pl_ncp_cuda_phase phase,
                                     const pl_ncp_cuda_rows *R, const pl_ncp_cuda_vecs *V,
                                     const pl_ncp_cuda_params *P, int last)
{
    k_phase<<<1, kThreads, 0, st>>>((int)phase, last, -1, 0, R, *V, *P);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_phase_run2(struct CUstream_st *st, pl_ncp_cuda_phase phase, int last,
                                   pl_ncp_cuda_phase phase2, int last2, const pl_ncp_cuda_rows *R,
                                   const pl_ncp_cuda_vecs *V, const pl_ncp_cuda_params *P)
{
    k_phase<<<1, kThreads, 0, st>>>((int)phase, last, (int)phase2, last2, R, *V, *P);
    return (int)cudaGetLastError();
}

extern "C" int ncp_cuda_capturing(struct CUstream_st *st)
{
    cudaStreamCaptureStatus status = cudaStreamCaptureStatusNone;
    /* an error answers "capturing": the caller then launches one by one, as before */
    if (cudaStreamIsCapturing(st, &status) != cudaSuccess) return 1;
    return status != cudaStreamCaptureStatusNone;
}
