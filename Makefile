# edmd: event-driven molecular dynamics of granular gases.
#   make run       the quick default sweep (sweeps/quick.json): phase table, files and a figure report
#                  (edmd-out/quick/report/index.html)
#   make figures   the report of the quick sweep, or of any sweep with OUT=dir
#   make test      everything CI checks (format, lints, Rust tests with the edmd-bench smoke run, Python
#                  tests, Slurm)
#   make check     daily work: format check, clippy and the Rust tests
#   make bench     collisions/s and peak bytes per particle over N and phi (or one case: D= N= PHI= EPS=)
#   make bench-nightly  the fixed benchmark matrix with history and regression flags
#   make bench-accuracy  run time against error (remedies, statistics, classification)
#   make test-slurm  sweeps on a real single-node Slurm (also part of make test): a 4-task array sweep
#                  equals a local run; a cancelled task is finished by rerunning the submit command
#   make stress    stress tests at full size (numerical stability; CI runs short versions)
#   make validate  long equilibrium-accuracy runs (chi against Luding / Carnahan-Starling)
#   make deps      system packages (libhdf5-dev, hdf5-tools) and the Python venv for analysis/
#                  (MEDIA=1: also ffmpeg and headless Chromium for MP4 movies and the page test)

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

.PHONY: all deps deps-system venv venv-base release-bin build run figures demo cli check test test-rust test-bin test-python lint lint-rust lint-python bench bench-smoke bench-nightly bench-accuracy stress test-slurm run-rust-tests run-python-tests run-slurm-tests validate clean

all: build

deps: deps-system venv

# System packages: Debian's, installed with apt-get when missing.
deps-system:
	@missing=""; for p in $(APT_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
		echo "installing:$$missing"; \
		if [ "$$(id -u)" = 0 ]; then apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing; \
		elif command -v sudo >/dev/null; then sudo apt-get update -qq && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing; \
		else echo "error: missing Debian packages:$$missing (install them as root)"; exit 1; fi; \
	fi

# The Python venv of analysis/: with its test extras (venv), or only what the report draws with
# (venv-base: numpy, h5py, matplotlib; a third of the time on a fresh machine, for make run).
venv venv-base: EXTRAS = $(if $(filter venv,$@),[test])
venv venv-base:
	@if [ -f analysis/pyproject.toml ]; then \
		[ -x $(VENV)/bin/python ] || $(PYTHON) -m venv $(VENV); \
		$(VENV)/bin/pip install -q -e 'analysis$(EXTRAS)'; \
	fi

build:
	$(CARGO) build --release --workspace --all-targets

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
	$(CARGO_ALONE) build --release -p edmd-cli --bin edmd

# The release binary the Python tests drive.
cli:
	$(CARGO) build --release -q -p edmd-cli --bin edmd

lint: lint-rust lint-python

lint-rust:
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets --features edmd/bench -- -D warnings

lint-python:
	$(VENV)/bin/ruff check analysis scripts tests

# Daily work: format check, lints and the Rust tests, without the Python, Slurm and benchmark parts.
check:
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets --features edmd/bench -- -D warnings
	$(CARGO) test $(RUST_TESTS)

# The Rust tests: unit, integration and doc tests (the examples are compiled by clippy, the criterion
# benchmarks by `make bench-smoke`).
RUST_TESTS := --workspace --lib --bins --tests

test-rust:
	$(CARGO) test $(RUST_TESTS)
	$(CARGO) test --workspace --doc

# The Python and Slurm tests drive the binary `cargo test` builds (test profile: opt-level 3 with debug
# assertions, no LTO): after test-rust it is already there, so `make test` links the sweep code once
# instead of twice (the LTO release build alone takes minutes on 2 cores). `make run` uses release.
TEST_BIN := $(CURDIR)/target/debug/edmd
# Cargo under `make -j` with its own job slots (one per core): make's jobserver is not handed to it,
# so that each part's output stays together (`--output-sync`).
CARGO_ALONE := env -u MAKEFLAGS -u MFLAGS $(CARGO)

test-bin:
	$(CARGO_ALONE) test -q $(RUST_TESTS) --no-run

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
	EDMD_BIN=$(TEST_BIN) $(VENV)/bin/python -m pytest -q analysis

run-slurm-tests:
	PY=$(CURDIR)/$(VENV)/bin/python EDMD=$(TEST_BIN) bash tests/slurm/test-slurm.sh

run-rust-tests:
	$(CARGO_ALONE) test -q $(RUST_TESTS)
	$(CARGO_ALONE) test -q --workspace --doc

# Everything CI checks, scheduled for a 2-core machine (docs/benchmarks.md, "The lean build"): the
# venv is made while the tests build; clippy runs after the build, whose build scripts and proc
# macros it shares; then the Rust, Python and Slurm tests run side by side (the Python tests are
# single-threaded, the Slurm test mostly waits for its scheduler), each printing its output when it
# ends. Without incremental caches: a fresh build writes none it would never read.
test: export CARGO_INCREMENTAL = 0
test: deps-system
	@$(MAKE) --no-print-directory -j2 --output-sync=target venv test-bin
	@$(MAKE) --no-print-directory lint
	@$(MAKE) --no-print-directory -j3 --output-sync=target run-rust-tests run-python-tests run-slurm-tests

# `make bench` runs the matrix; `make bench D=2 N=10000 PHI=0.3 [EPS=1]` runs one case and ends
# with `collisions_per_s=<number> bytes_per_particle=<number>`.
bench:
ifdef N
	$(CARGO) run --profile dist -q --bin edmd-bench -- --d $(or $(D),2) --n $(N) --phi $(or $(PHI),0.3) --eps $(or $(EPS),1.0)
else
	$(CARGO) run --profile dist -q --bin edmd-bench -- --matrix
endif

# Stress tests at full size (10^8 elastic collisions, T/T0 < 1e-1000, N = 10^7 disks, 2000 fuzz
# cases); `cargo test` runs short versions. Figures: docs/benchmarks.md.
stress:
	$(CARGO) test -p edmd-core --test engine -- --ignored --nocapture --test-threads 1 stress:: fuzz:: deep_cooling::large

# The nightly matrix (D, N, phi, eps): appends to benches/history.jsonl, prints a table and flags
# cases > 10 % slower than the previous entry on this machine (exit 1); then, where the peer codes are
# found (EDMD_PEERS=DIR), edmd/peer ratios side by side. NIGHTLY_ARGS="--only D=2,N=10000".
bench-nightly:
	$(CARGO) build --profile dist -q --bin edmd-bench
	$(PYTHON) scripts/bench-nightly.py $(NIGHTLY_ARGS)

# Run time against error: collapse remedies, statistics, classification (table + PNG in bench-out/accuracy).
bench-accuracy: deps
	$(CARGO) build --release -q --bin edmd-accuracy -p edmd
	$(CARGO) build --release -q -p edmd-cli --bin edmd
	$(VENV)/bin/python scripts/bench-accuracy.py -o bench-out/accuracy


validate:
	$(CARGO) test --release -p edmd-core --test engine -- --ignored --nocapture --test-threads 1 equilibrium::
	$(CARGO) test --release -p edmd-sweep --test regimes -- --ignored --nocapture

clean:
	$(CARGO) clean
	rm -rf $(VENV)
