# The two commands: `make demo` and `make test`. Each installs missing Debian packages,
# configures, builds and runs. Other targets are conveniences for developers.
SHELL := /bin/bash
BUILD_DIR ?= build
# Build and test jobs: the machine's cores, at most 8 (a sanitizer compile of the larger files
# takes about 2 GB).
JOBS ?= $(shell n=$$(nproc 2>/dev/null || echo 2); [ "$$n" -gt 8 ] && n=8; echo $$n)
CMAKE_FLAGS ?=

PACKAGES := cmake ninja-build g++ pkg-config libgtest-dev libgmock-dev libbenchmark-dev \
  libboost-random-dev libboost-math-dev libglm-dev zlib1g-dev libtomlplusplus-dev libstb-dev \
  libcairo2-dev fonts-dejavu-core \
  nlohmann-json3-dev libcli11-dev libfmt-dev libeigen3-dev libsqlite3-dev \
  nettle-dev libnlopt-dev libusb-1.0-0-dev \
  libglfw3-dev libimgui-dev libhidapi-dev xvfb xauth libgl1-mesa-dri umockdev libumockdev-dev \
  python3-pandas

# Packages wanted for a command rather than by name, as COMMAND:PACKAGE: the BIDS validator
# test (tests/runner/bids_validator/) needs node and npm. Debian 12 has them as nodejs (Node 18)
# and npm; a Node.js installed otherwise (e.g. NodeSource's nodejs, which brings its own npm and
# conflicts with Debian's npm package) is used as it is.
COMMAND_PACKAGES := node:nodejs npm:npm

SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

# `make fuzz` only: clang and libFuzzer's runtime (libclang_rt.fuzzer-x86_64.a).
FUZZ_PACKAGES := clang libclang-rt-14-dev
# Executions per target of `make fuzz`.
FUZZ_RUNS ?= 1000000

.PHONY: all deps fuzz-deps build build-asan demo test test-release test-asan bench fuzz \
  format clean validator-prefetch

all: build

deps:
	@missing=$$(for p in $(PACKAGES); do \
	  dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'install ok installed' || echo $$p; done; \
	  for c in $(COMMAND_PACKAGES); do command -v $${c%%:*} >/dev/null || echo $${c#*:}; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing missing Debian packages:" $$missing; \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get update -qq && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null; \
	fi

# Both builds are unity builds: CMake compiles each target's sources in batches of 16 per
# translation unit, so the heavy shared headers (toml++, nlohmann/json, fmt, Boost, Eigen,
# gtest) are compiled, and the templates they instantiate emitted, once per batch rather than
# once per source. Measured on the 2-core machine, clean at -j2: release 727 -> 396 CPU-s
# (6.1 -> 3.3 min), sanitizer 1189 -> 715 CPU-s (10.0 -> 6.0 min) with batches of 8, CMake's
# default; as the code grew, batches of 8 came to 536 and 890 summed ninja job-s (idle
# machine, 8ef553a) and batches of 16 to 448 and 743, the builds' wall time 270 -> 220 s and
# 446 -> 376 s. Only runner_tests still needs two batches; the largest unit (analysis with
# its model gap, sanitizer build) takes 70-92 s and 2.0 GB. A plain `cmake -S . -B dir`
# stays a per-file build.
# The test programs' own sources are built at -O1 here and -O0 in the sanitizer build
# (BURRLAB_TEST_CXX_FLAGS, tests/CMakeLists.txt); the sanitizer build registers each test binary
# as shards rather than one ctest test per case (BURRLAB_TEST_SHARDS).
$(BUILD_DIR)/release/build.ninja: | deps
	cmake -S . -B $(BUILD_DIR)/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON \
	  -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 -DBURRLAB_TEST_CXX_FLAGS=-O1 $(CMAKE_FLAGS)

# The sanitizer build at -O0 with line tables only, but the libraries the tests spend their
# time in at -O1 (BURRLAB_HOT_CXX_FLAGS, cmake/BurrlabOptions.cmake: sim/, sim/base/, stimuli/,
# protocols/, analysis/ with its model gap, runner's studies layer). The build, not the tests,
# is most of the sanitizer half of `make test`; every ASan+UBSan check is kept and reports
# still carry file:line. Measured on the 2-core machine, sharing it with another build,
# CPU-s (user+sys): clean build all -O1 1189, -O1 for the simulator only 984; ctest all -O1
# 473, -O1 for the simulator only 834 (analysis/, protocols/ and the studies at -O0 doubled
# their tests), with the libraries above at -O1 455. On an idle machine the gain is small:
# the build's summed ninja job time was 874 s all -O1 (2beebcf) and 859 s so (f4d6a43).
$(BUILD_DIR)/asan/build.ninja: | deps
	cmake -S . -B $(BUILD_DIR)/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O0 -g1 -DNDEBUG" -DBURRLAB_HOT_CXX_FLAGS=-O1 \
	  -DBURRLAB_SANITIZE=ON -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 \
	  -DBURRLAB_TEST_CXX_FLAGS=-O0 \
	  -DBURRLAB_TEST_SHARDS=4 $(CMAKE_FLAGS)

build: deps $(BUILD_DIR)/release/build.ninja
	cmake --build $(BUILD_DIR)/release -j $(JOBS)

build-asan: deps $(BUILD_DIR)/asan/build.ninja
	cmake --build $(BUILD_DIR)/asan -j $(JOBS)

demo: deps $(BUILD_DIR)/release/build.ninja
	cmake --build $(BUILD_DIR)/release -j $(JOBS) --target burrlab
	$(BUILD_DIR)/release/runner/burrlab demo --out $(BUILD_DIR)/demo

# The BIDS validator test's npm install (minutes, mostly waiting on the registry) starts in the
# background before the build, so it overlaps the compilation; the test's fixture waits for it.
validator-prefetch: deps
	@mkdir -p $(BUILD_DIR)/release
	@bash tests/runner/bids_validator/install.sh $(BUILD_DIR)/release/bids-validator \
	  > $(BUILD_DIR)/release/bids-validator-install.log 2>&1 &

test-release: validator-prefetch build
	cd $(BUILD_DIR)/release && ctest --output-on-failure -j $(JOBS)

test-asan: build-asan
	cd $(BUILD_DIR)/asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS)

# The whole suite: optimised build first, then the same tests under ASan+UBSan; the last
# lines are ctest's summary of the sanitizer run.
test: test-release test-asan

fuzz-deps: deps
	@missing=$$(for p in $(FUZZ_PACKAGES); do \
	  dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing missing Debian packages:" $$missing; \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get update -qq && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null; \
	fi

$(BUILD_DIR)/fuzz/build.ninja: | fuzz-deps
	CC=clang CXX=clang++ cmake -S . -B $(BUILD_DIR)/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" -DBURRLAB_LIBFUZZER=ON -DBURRLAB_BUILD_TESTS=OFF \
	  -DCMAKE_UNITY_BUILD=ON $(CMAKE_FLAGS)

# libFuzzer over every parser (tests/fuzz/README.md): FUZZ_RUNS executions per target from a
# copy of its corpus, then a table of executions, crashes and timeouts per target.
fuzz: fuzz-deps $(BUILD_DIR)/fuzz/build.ninja
	cmake --build $(BUILD_DIR)/fuzz -j $(JOBS) --target fuzzers
	tests/fuzz/run_libfuzzer.sh $(BUILD_DIR)/fuzz $(FUZZ_RUNS)

bench: build
	$(BUILD_DIR)/release/runner/burrlab sim bench

format:
	git ls-files '*.cc' '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR)
