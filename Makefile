# The two commands of the README: `make run` and `make test`.
BUILD ?= build
JOBS  ?= $(shell nproc)
# `make install DESTDIR=/staging PREFIX=/opt/peri`: where the installation goes (README;
# PREFIX defaults to /usr/local and, like PORTABLE, is kept by the build folder once given)
PREFIX ?=
DESTDIR ?=
# `make build PORTABLE=1`: binaries for any processor of the architecture (no -march=native);
# PORTABLE=0 goes back to -march=native
PORTABLE ?=
CMAKE_OPTIONS := $(if $(PREFIX),-DCMAKE_INSTALL_PREFIX=$(PREFIX)) \
                 $(if $(PORTABLE),-DPERI_NATIVE=$(if $(filter 1 yes on ON true,$(PORTABLE)),OFF,ON))

.PHONY: all deps configure build run test install bench bench-gpu bench-peers bench-plate bench-coupling bench-notch invariance clean

all: build

deps:
	@scripts/install-deps

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_OPTIONS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

run: build
	$(BUILD)/peri run examples/quickstart.yaml --output output/quickstart
	@echo "output: output/quickstart/ (quickstart.pvd, VTU frames, history.csv, damage.png)"

test: build
	@cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

# the program, libperi (static and shared), the headers, peri.pc and the Python module
install: build
	@DESTDIR="$(DESTDIR)" cmake --install $(BUILD)

bench: build
	@scripts/install-deps --bench
	@bench/run
	@PERI=$(BUILD)/peri bench/dayone
	@PERI=$(BUILD)/peri bench/refined_notch

# Peridigm (built from ../shared/peers, Debian's Trilinos) and peri on the fragmenting cylinder
# the GPU back end (docs/gpu.md): a build with it (PERI_CUDA=AUTO finds nvcc and a GPU)
bench-gpu: build
	@PERI=$(BUILD)/peri bench/gpu/run

bench-peers: build
	@scripts/install-deps --peers
	@PERI=$(BUILD)/peri BUILD=$(BUILD) bench/peers/cylinder_side_by_side

# quasi-static solvers on the plate with a hole at ~10^6 unknowns (over an hour; not in `make test`)
bench-plate: build
	@PERI=$(BUILD)/peri bench/plate_solvers

# coupled (PD-FEM, adaptive switching) against all-PD three-point bending: unknowns, time, memory
bench-coupling: build
	@PERI=$(BUILD)/peri bench/coupling_3pb

# the refined notch on its graded grid against the uniformly fine beam (docs/variable_horizon.md)
bench-notch: build
	@PERI=$(BUILD)/peri bench/refined_notch

# every example and test deck (the fuzz seeds) on 1 and 2 threads and 1 and 3 MPI ranks, their
# history.csv compared (docs/reliability.md, "Determinism"; about 40 minutes on 2 cores; not in `make test`)
invariance: build
	@scripts/invariance_sweep --peri $(BUILD)/peri

clean:
	rm -rf $(BUILD) output
