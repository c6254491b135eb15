# The two commands of README.md: `make run` and `make test`. Both install missing Debian packages first.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=

.PHONY: run test build deps configure clean bench-error bench-cornell36 bench-throughput sanitize fuzz bench-raycast bench-e2e bench-micro bench-mpi bench-offload bench-profile

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

run: build
	./$(BUILD_DIR)/ptview $(ARGS)

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) --timeout 900

# Error against time for every strategy and sampler; tables to stdout, plots to docs/img (see docs/BENCHMARKS.md).
# Issue 11's targets 2 and 3 are printed after the table, as medians of three runs of every pair (--repeat).
bench-error: build
	@PTVIEW_WITH_BENCH_DEPS=1 bash scripts/install-deps.sh
	./$(BUILD_DIR)/bench/bench_time_vs_error --size 128 --max-spp 64 --ref-spp 1024 --repeat 3 --csv $(BUILD_DIR)/time_vs_error.csv
	/usr/bin/python3 bench/plot_time_vs_error.py $(BUILD_DIR)/time_vs_error.csv docs/img
	/usr/bin/python3 bench/plot_convergence.py $(BUILD_DIR)/time_vs_error docs/img

# Issue 11's efficiency target: bench/data/cornell36.obj with its light emitting, 256x256, depth 8, 2 threads,
# against a 4096-spp reference rendered as two halves (cached in $(BUILD_DIR)/refcache), reference noise subtracted.
bench-cornell36: build
	./$(BUILD_DIR)/bench/bench_time_vs_error --scenes cornell36 --size 256 --max-spp 256 --ref-spp 4096 --max-depth 8 --threads 2 --cache $(BUILD_DIR)/refcache --csv $(BUILD_DIR)/cornell36.csv
	/usr/bin/python3 bench/plot_time_vs_error.py $(BUILD_DIR)/cornell36.csv docs/img

bench-throughput: build
	./$(BUILD_DIR)/bench/bench_render_throughput --csv $(BUILD_DIR)/render_throughput.csv

# ptview against the Embree path tracer tutorial on bench/data/cornell36.obj; table to stdout, CSV in $(BUILD_DIR).
bench-e2e: build
	@PTVIEW_WITH_BENCH_DEPS=1 bash scripts/install-deps.sh
	bash bench/e2e_vs_embree.sh $(BUILD_DIR)

# spp/s of 1 process x 2 threads against 2 MPI ranks x 1 thread, and the cost of one reduction (bench/mpi_scaling.sh).
bench-mpi: build
	bash bench/mpi_scaling.sh $(BUILD_DIR)

# Viewer restart latency p50/p95 under an edit storm: 1 process against 2 MPI ranks (bench/offload_latency.sh).
bench-offload: build
	bash bench/offload_latency.sh $(BUILD_DIR)

# Google Benchmark micro benchmarks of the triangle and box tests and the sampling warps.
bench-micro: build
	./$(BUILD_DIR)/bench/bench_micro_accel

# Issue 11's target 5: where a cornell36 frame's time goes (perf record -e cpu-clock, 1 thread), and ray casting's share.
bench-profile: build
	@PTVIEW_WITH_BENCH_DEPS=1 bash scripts/install-deps.sh
	bash bench/profile_frame.sh $(BUILD_DIR)

# Our BVH against Embree 3 (libembree-dev, a bench dependency): ray throughput, agreement, build (bench/raycast.cpp).
# Re-configures after installing the dependencies so that a build configured without Embree picks it up.
bench-raycast: build
	@PTVIEW_WITH_BENCH_DEPS=1 bash scripts/install-deps.sh
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target bench_raycast
	./$(BUILD_DIR)/bench/bench_raycast --csv $(BUILD_DIR)/raycast.csv

# The whole suite under ASan + UBSan, the concurrency tests under TSan; each fuzzer for FUZZ_SECONDS.
FUZZ_SECONDS ?= 60
sanitize:
	@PTVIEW_WITH_CI_TOOLS=1 bash scripts/install-deps.sh
	bash scripts/sanitizers.sh
fuzz:
	@PTVIEW_WITH_CI_TOOLS=1 bash scripts/install-deps.sh
	bash scripts/fuzz.sh $(FUZZ_SECONDS)

clean:
	rm -rf $(BUILD_DIR)
