# Thin wrapper over CMake/CTest.  The two commands of the quick start:
#   make demo   install what is missing, build, run the default scene
#   make test   build, run the whole suite, then again under ASan+UBSan (that
#               build has no CUDA and no MPI: the MPI tests run in the first pass),
#               then check that both builds document the same scene format
#               (`pliant doc`, byte for byte); the Python package's tests
#               run between the two passes (make test-python)
# make test and CI turn warnings into errors (PLIANT_WERROR=ON); a plain
# build (make build, cmake) does not, so a newer compiler never stops it.
BUILD ?= build
ASAN_BUILD ?= build-asan
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=
DEMO_SCENE ?= scenes/twisting_bar_small.xml
DEMO_OUT ?= out/demo

# the Python package (docs/python.md): a venv with NumPy, pytest, gymnasium and
# scikit-build-core from PyPI; pip builds the package from the checkout into
# $(PY_BUILD)/cmake (kept: later builds are incremental)
PY_BUILD ?= build-python
PYTHON ?= python3

FUZZ_BUILD ?= build-fuzz
FUZZ_COV_BUILD ?= build-fuzz-cov
# seconds each fuzz target runs (make fuzz FUZZ_SECONDS=600 for the 10-minute runs of docs/fuzzing.md)
FUZZ_SECONDS ?= 180
# targets to run (default: all of tests/fuzz)
FUZZ_TARGETS ?=

.PHONY: all deps deps-fuzz configure build demo test test-fast test-asan test-doc bench docs pictures \
	python test-python \
	clean fuzz fuzz-build fuzz-coverage

all: build

deps:
	@sh cmake/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo $(CMAKE_FLAGS)

configure: $(BUILD)/CMakeCache.txt

build: configure
	cmake --build $(BUILD) -j $(JOBS)

demo: build
	$(BUILD)/bin/pliant run $(DEMO_SCENE) -n 100 --out $(DEMO_OUT) --timings $(DEMO_OUT)/timings.json
	@echo "demo: open $(DEMO_OUT)/*.pvd in ParaView"

test-fast: configure
	cmake -S . -B $(BUILD) -DPLIANT_WERROR=ON
	cmake --build $(BUILD) -j $(JOBS)
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

$(ASAN_BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DPLIANT_SANITIZE=ON -DPLIANT_CUDA=OFF \
	  -DPLIANT_MPI=OFF $(CMAKE_FLAGS)

test-asan: $(ASAN_BUILD)/CMakeCache.txt
	cmake -S . -B $(ASAN_BUILD) -DPLIANT_WERROR=ON
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --output-on-failure -j $(JOBS)

# The scene format does not depend on the build: the component reference of
# the CUDA build and of the ASan build (no CUDA) must be equal.
test-doc:
	env -u PLIANT_PLUGIN_PATH $(BUILD)/bin/pliant doc $(BUILD)/components.md >/dev/null
	env -u PLIANT_PLUGIN_PATH ASAN_OPTIONS=detect_leaks=1 $(ASAN_BUILD)/bin/pliant doc \
	  $(ASAN_BUILD)/components.md >/dev/null
	@cmp -s $(BUILD)/components.md $(ASAN_BUILD)/components.md || \
	  { diff $(BUILD)/components.md $(ASAN_BUILD)/components.md; \
	    echo "test-doc: FAIL: pliant doc differs between $(BUILD) and $(ASAN_BUILD)"; exit 1; }
	@echo "test-doc: ok, $(BUILD) and $(ASAN_BUILD) document the same components"

# (the stamp is written last: a venv whose pip install failed is made again)
$(PY_BUILD)/venv/ready: | deps
	rm -rf $(PY_BUILD)/venv
	$(PYTHON) -m venv $(PY_BUILD)/venv
	$(PY_BUILD)/venv/bin/pip install -q "scikit-build-core>=0.10" "numpy>=1.22" pytest "gymnasium>=0.29"
	touch $@

python: $(PY_BUILD)/venv/ready
	CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) $(PY_BUILD)/venv/bin/pip install -q --no-build-isolation \
	  --no-deps -Cbuild-dir=$(PY_BUILD)/cmake .

# pytest in the venv; PLIANT_CLI lets the tests check `pliant run script.py`
test-python: python
	cd python/tests && PLIANT_CLI=$(abspath $(BUILD))/bin/pliant \
	  $(abspath $(PY_BUILD))/venv/bin/python -m pytest -q -rsx -p no:cacheprovider .

test: test-fast test-python test-asan test-doc

# Fuzzing (tests/fuzz, docs/fuzzing.md): clang + libFuzzer, not part of `make test`
# (which replays the seeds and the regression inputs).  Runs under nice -n 19.
deps-fuzz:
	@sh cmake/install-deps.sh fuzz

$(FUZZ_BUILD)/CMakeCache.txt: | deps-fuzz
	CC=clang cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPLIANT_FUZZ=ON \
	  -DPLIANT_TESTS=OFF -DPLIANT_CUDA=OFF $(CMAKE_FLAGS)

fuzz-build: $(FUZZ_BUILD)/CMakeCache.txt
	nice -n 19 cmake --build $(FUZZ_BUILD) -j $(JOBS)

fuzz: fuzz-build
	nice -n 19 sh tests/fuzz/run_fuzz.sh $(FUZZ_BUILD) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

$(FUZZ_COV_BUILD)/CMakeCache.txt: | deps-fuzz
	CC=clang cmake -S . -B $(FUZZ_COV_BUILD) -DCMAKE_BUILD_TYPE=Debug -DPLIANT_FUZZ_COVERAGE=ON \
	  -DPLIANT_TESTS=OFF -DPLIANT_CUDA=OFF $(CMAKE_FLAGS)

# line coverage of each target's reader over the corpus `make fuzz` grew
fuzz-coverage: $(FUZZ_COV_BUILD)/CMakeCache.txt
	nice -n 19 cmake --build $(FUZZ_COV_BUILD) -j $(JOBS)
	nice -n 19 sh tests/fuzz/coverage.sh $(FUZZ_COV_BUILD) $(FUZZ_BUILD) $(FUZZ_TARGETS)

bench: build
	sh tests/bench/run.sh $(BUILD)

docs: build
	$(BUILD)/bin/pliant doc docs/components.md
	$(BUILD)/bin/pliant doc --sofa docs/sofa-vocabulary.md

# one picture of every scene (pliant render, off screen) for docs/scenes.md
pictures: build
	sh docs/make_pictures.sh $(BUILD)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(FUZZ_BUILD) $(FUZZ_COV_BUILD) $(PY_BUILD) out
