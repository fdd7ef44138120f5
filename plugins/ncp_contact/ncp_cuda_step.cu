/* ncp_cuda_step.cu - the constraint update of Algorithm 4 on the GPU, in
 * phases between its W products (see ncp_cuda.h for the sequence): one
 * single-block kernel a phase (the phases' code: ncp_cuda_phases.cuh). */
#include "ncp_cuda_phases.cuh"

namespace {

__global__ void __launch_bounds__(kThreads)
    k_phase(int phase, const pl_ncp_cuda_rows *__restrict__ Rp, pl_ncp_cuda_vecs V,
            pl_ncp_cuda_params P, int last)
{
    const pl_ncp_cuda_rows R = *Rp; /* the step's rows (a graph keeps only the address) */
    __shared__ double sh[kRedShared];
    red rd = {sh, 0, 32};
    run_phase<kThreads>(phase, R, V, P, last, rd);
}

} // namespace

extern "C" int ncp_cuda_phase_run(struct CUstream_st *st, pl_ncp_cuda_phase phase,
                                     const pl_ncp_cuda_rows *R, const pl_ncp_cuda_vecs *V,
                                     const pl_ncp_cuda_params *P, int last)
{
    k_phase<<<1, kThreads, 0, st>>>((int)phase, R, *V, *P, last);
    return (int)cudaGetLastError();
}
