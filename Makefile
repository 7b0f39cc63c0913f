# vitrum — thin entry points. `make run` and `make test` both: install missing Debian 12 packages (as root,
# quietly, only when missing), configure and build Release into build/, then run the quickstart scene or ctest.
PACKAGES := cmake g++ make libeigen3-dev libfftw3-dev libhdf5-dev libvtk9-dev libcgal-dev \
            libtomlplusplus-dev libcli11-dev libgtest-dev libbenchmark-dev nlohmann-json3-dev \
            python3-matplotlib pkg-config libopenmpi-dev openmpi-bin python3-h5py
BUILD    ?= build
JOBS     ?= $(shell nproc)
SHELL    := /bin/bash

.PHONY: run test build deps bench clean

run: build
	./$(BUILD)/vitrum run examples/quickstart.toml --out out/quickstart

test: build
	cd $(BUILD) && OMP_NUM_THREADS=2 ctest --output-on-failure --timeout 600

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > /dev/null
	cmake --build $(BUILD) -j $(JOBS)

deps:
	@missing=$$(for p in $(PACKAGES); do dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q ' ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "vitrum: installing missing Debian packages:" $$missing; \
	  if [ "$$(id -u)" != 0 ]; then echo "vitrum: need root to install packages (or install them yourself)"; exit 2; fi; \
	  export DEBIAN_FRONTEND=noninteractive; \
	  apt-get update -qq && apt-get install -y -qq --no-install-recommends $$missing > /dev/null; \
	fi

bench: build
	bash bench/run_benchmarks.sh

clean:
	rm -rf $(BUILD)

# The paper's tables and figures (examples/paper/README.md): `make paper-NAME` for one, `make paper` for all
# (hours), `make paper-quick` for all at the reduced resolution (about a minute each); QUICK=1 does the same
# for one target. Each prints its expected wall time on 2 cores first and writes out/paper/NAME/ (quick:
# out/paper/quick/NAME/). THREADS: threads per run.
PYTHON  ?= /usr/bin/python3
THREADS ?= 2
PAPER   := table1 table3 table4 fig6 fig10 fig13 fig14 fig15
PAPER_FLAGS = --threads $(THREADS) --vitrum $(BUILD)/vitrum $(if $(QUICK),--quick)

.PHONY: paper paper-quick $(addprefix paper-,$(PAPER))

$(addprefix paper-,$(PAPER)): paper-%: build
	$(PYTHON) examples/paper/reproduce.py $* $(PAPER_FLAGS)

paper: build
	$(PYTHON) examples/paper/reproduce.py all $(PAPER_FLAGS)

paper-quick: build
	$(PYTHON) examples/paper/reproduce.py all $(PAPER_FLAGS) --quick
