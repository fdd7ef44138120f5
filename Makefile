# Thin wrapper over CMake/CTest.  The two commands of the quick start:
#   make demo   install what is missing, build, run the default scene
#   make test   build, run the whole suite, then again under ASan+UBSan (that
#               build has no CUDA and no MPI: the MPI tests run in the first pass)
BUILD ?= build
ASAN_BUILD ?= build-asan
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=
DEMO_SCENE ?= scenes/twisting_bar_small.xml
DEMO_OUT ?= out/demo

.PHONY: all deps configure build demo test test-fast test-asan bench docs pictures clean

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

test-fast: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

$(ASAN_BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DPLIANT_SANITIZE=ON -DPLIANT_CUDA=OFF \
	  -DPLIANT_MPI=OFF $(CMAKE_FLAGS)

test-asan: $(ASAN_BUILD)/CMakeCache.txt
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --output-on-failure -j $(JOBS)

test: test-fast test-asan

bench: build
	sh tests/bench/run.sh $(BUILD)

docs: build
	$(BUILD)/bin/pliant doc docs/components.md

# one picture of every scene (pliant render, off screen) for docs/scenes.md
pictures: build
	sh docs/make_pictures.sh $(BUILD)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) out
