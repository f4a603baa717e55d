# The two commands of the README: `make run` and `make test`.
BUILD ?= build
JOBS  ?= $(shell nproc)

.PHONY: all deps configure build run test bench bench-plate clean

all: build

deps:
	@scripts/install-deps

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

run: build
	$(BUILD)/peri run examples/quickstart.yaml --output output/quickstart
	@echo "output: output/quickstart/ (quickstart.pvd, VTU frames, history.csv, damage.png)"

test: build
	@cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

bench: build
	@scripts/install-deps --bench
	@bench/run
	@PERI=$(BUILD)/peri bench/dayone

# quasi-static solvers on the plate with a hole at ~10^6 unknowns (over an hour; not in `make test`)
bench-plate: build
	@PERI=$(BUILD)/peri bench/plate_solvers

clean:
	rm -rf $(BUILD) output
