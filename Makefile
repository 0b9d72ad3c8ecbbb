# Thin wrapper over CMake so the README's two commands work on a fresh Debian 12 machine:
#   make run   set up, build, render the default scene (window with a display, PNG without)
#   make test  set up, build Release (GCC and clang) and ASan+UBSan (clang), run the tests and a short fuzz run
JOBS ?= $(shell nproc)
SCENE ?= scenes/default.json
FUZZ_SECONDS ?= 15

.PHONY: all setup build run test test-release build-clang test-clang test-sanitize fuzz bench debug package clean

all: build

setup:
	@bash scripts/setup.sh

build: setup
	cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build build -j $(JOBS)

debug: setup
	cmake -S . -B build-debug -DCMAKE_BUILD_TYPE=Debug >/dev/null
	cmake --build build-debug -j $(JOBS)

run: build
	@bash scripts/run-default.sh build $(SCENE)

test-release: build
	cd build && ctest --output-on-failure -j $(JOBS)

# The sanitizer build is clang's, so CI also holds clang to -Werror and runs the suite with its
# stack layout and code (an uninitialised struct that reads as zeros under GCC shows here). It
# leaves out the tests labelled release-only (CMakeLists.txt says which and why).
test-sanitize: setup
	CC=clang cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DSL_SANITIZE=ON >/dev/null
	cmake --build build-asan -j $(JOBS)
	cd build-asan && ctest --output-on-failure -j $(JOBS) -LE release-only

# A clang Release build, held to -Werror: clang at -O2 reports what its -O1 sanitizer build does
# not (an `omp simd` loop it cannot vectorize in a file that does not allow it). `make test`
# builds it; test-clang also runs every test in it.
build-clang: setup
	CC=clang cmake -S . -B build-clang -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build build-clang -j $(JOBS)

test-clang: build-clang
	cd build-clang && ctest --output-on-failure -j $(JOBS)

fuzz: setup
	CC=clang cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Debug -DSL_FUZZ=ON -DSL_SANITIZE=ON \
	  -DSL_BUILD_TESTS=OFF -DSL_BUILD_BENCH=OFF >/dev/null
	cmake --build build-fuzz -j $(JOBS)
	bash scripts/fuzz.sh build-fuzz $(FUZZ_SECONDS)

test: test-release build-clang test-sanitize fuzz
	@echo "make test: all passed"

# The quick benchmarks (a few minutes); bench/README.md lists them all, with vs-gl.sh and speed-vs-error.sh.
bench: build
	OMP_WAIT_POLICY=passive ./build/bench_raster --threads 1,2 --tiles 64 --frames 5
	OMP_WAIT_POLICY=passive ./build/bench_shading --frames 3
	OMP_WAIT_POLICY=passive bash bench/vs-gl.sh build 3 5

# Debian packages in build-deb/ (docs/install.md): installed under /usr, not tuned for this CPU.
package: setup
	cmake -S . -B build-deb -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr -DSL_NATIVE=OFF \
	  -DSL_BUILD_TESTS=OFF -DSL_BUILD_BENCH=OFF >/dev/null
	cmake --build build-deb -j $(JOBS)
	cd build-deb && cpack -G DEB

clean:
	rm -rf build build-debug build-asan build-clang build-fuzz build-deb
