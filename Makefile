# rheosim: the only two set-up commands on a fresh Debian 12 machine are `make demo` and
# `make test`; both install what is missing, build, and run.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

.PHONY: all deps build demo test bench clean

all: build

deps:
	@tools/install-deps.sh

build: deps
	@cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) > $(BUILD_DIR).configure.log 2>&1 || { cat $(BUILD_DIR).configure.log; exit 1; }
	@cmake --build $(BUILD_DIR) -j $(JOBS)

demo: build
	$(BUILD_DIR)/bin/rheosim run cases/quickstart.yaml --out results/quickstart
	$(BUILD_DIR)/bin/rheosim run cases/suspension_demo.yaml --out results/suspension_demo
	@echo "reports: results/quickstart/report.html results/suspension_demo/report.html"

test: build
	cd $(BUILD_DIR) && ctest -L 'unit|validation' --output-on-failure -j $(JOBS) --timeout 1500

bench: build
	bench/run $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR) $(BUILD_DIR).configure.log
