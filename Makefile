# polyloc: `make run` and `make test` do everything on a fresh Debian 12 machine (as root):
# install the Debian packages that are missing, configure a Release build, build, then run.
BUILD_DIR ?= build
JOBS      ?= $(shell nproc)

# Debian 12 packages the build needs; `make deps` installs the missing ones, quietly.
# clang and its runtime build the libFuzzer targets (fuzz/), which `make test` runs briefly.
# EGL/GLES and Mesa's drivers: the GPU path (kernels/gpu), tested on llvmpipe where no GPU is.
# node/npm (for the cross-check of our MCAP/CDR against the reference JS readers) are taken
# from PATH when present, else from Debian.
# websocketpp + asio: the live view's server (service/live); chromium: its page's test, headless.
APT_PACKAGES := g++ cmake ninja-build pkg-config \
  libeigen3-dev libembree-dev libtbb-dev libassimp-dev libyaml-cpp-dev \
  libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev \
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev \
  libfastcdr-dev liboctomap-dev libsqlite3-dev libzstd-dev liblz4-dev zlib1g-dev \
  libgtest-dev libgmock-dev libbenchmark-dev \
  libopenmpi-dev openmpi-bin \
  clang libclang-rt-14-dev \
  pybind11-dev python3-dev python3-numpy python3-pytest \
  libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri \
  libwebsocketpp-dev libasio-dev chromium

.PHONY: run test deps configure build bench bench-carmen check-figures clean

# polylocd on the bundled lab, fed by a live simulation of the lab tour at real time (the
# stand-in for a robot): status on the terminal (pose, error against ground truth, latency,
# rates), then a PNG of map, true path and the poses polylocd published (build/run.png).
RUN_DURATION ?= 60
run: build
	@$(BUILD_DIR)/bin/polylocd --config maps/config/lab.yaml & pid=$$!; \
	  $(BUILD_DIR)/bin/polyloc play --scenario maps/scenarios/lab_tour.yaml --shm lab --duration $(RUN_DURATION) \
	    --plot $(BUILD_DIR)/run.png; rc=$$?; \
	  kill -INT $$pid; wait $$pid; echo "picture: $(BUILD_DIR)/run.png"; exit $$rc

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

deps:
	@missing=""; for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'install ok installed' || missing="$$missing $$p"; \
	done; \
	command -v npm >/dev/null || missing="$$missing nodejs npm"; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  if [ "$$(id -u)" != 0 ]; then echo "run as root (or sudo apt-get install$$missing)" >&2; exit 1; fi; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null \
	    || { echo "apt-get install failed for:$$missing" >&2; exit 1; }; \
	fi

configure: deps
	@[ -f $(BUILD_DIR)/build.ninja ] || cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

bench: build
	$(BUILD_DIR)/bin/bench_raycast --benchmark_counters_tabular=true

# The real-log tables of docs/benchmarks.md on all eight shared logs (polyloc's and the end-point
# map, mid drift and the log's own odometry, 10 global starts per map; 35 minutes on 2 cores),
# checked against the claimed figures (docs/carmen_figures.json): fails on a 1.5x regression.
# CARMEN_ARGS=--matrix runs every map style x drift level x decimation (a few hours; only the
# claimed cases are checked); LOGS=... runs fewer logs (bench/carmen_table.sh).
CARMEN_ARGS ?= --map-styles polyloc,endpoint --drift mid --decimate 1 --global-trials 10
bench-carmen: build
	CHECK=docs/carmen_figures.json ARGS="$(CARMEN_ARGS)" bench/carmen_table.sh $(BUILD_DIR)

# Every figure docs/benchmarks.md and README.md claim (docs/figures.json), re-measured with the
# commands the doc quotes, the real-log table included (an hour or more on 2 shared cores): prints
# claimed vs measured and fails when one regressed by 1.5x. FIGURES_ARGS='--only REGEX' runs some groups,
# '--with-slow' adds the polylocd soak and end-to-end latency (real time), '--list' shows them.
check-figures: build
	bench/check_figures.py $(BUILD_DIR) $(BUILD_DIR)/figures $(FIGURES_ARGS)

clean:
	rm -rf $(BUILD_DIR)
