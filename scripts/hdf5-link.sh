#!/usr/bin/env bash
# How the edmd binary links HDF5: prints `system` or `bundled`; with --why, the choice and its reason
# on one line. `make` builds with `--features edmd-cli/bundled-hdf5` when this says `bundled`.
#
#   HDF5_LINK=system|bundled   the user's choice, taken as it is
#   Debian with root or sudo   system: make deps installs libhdf5-dev with apt-get
#   HDF5_DIR set               system: the HDF5 there (e.g. after `module load hdf5` on a cluster)
#   pkg-config finds hdf5      system
#   otherwise                  bundled: HDF5 built from its sources (cmake, a C compiler) and linked
#                              statically; nothing needs root
set -euo pipefail
choice="" why=""
if [ -n "${HDF5_LINK:-}" ]; then
    case "$HDF5_LINK" in
        system|bundled) choice=$HDF5_LINK; why="HDF5_LINK=$HDF5_LINK" ;;
        *) echo "error: HDF5_LINK=$HDF5_LINK: system or bundled" >&2; exit 2 ;;
    esac
elif command -v dpkg >/dev/null && command -v apt-get >/dev/null \
    && { [ "$(id -u)" = 0 ] || sudo -n true 2>/dev/null; }; then
    choice=system; why="Debian with root: libhdf5-dev from apt-get"
elif [ -n "${HDF5_DIR:-}" ]; then
    choice=system; why="HDF5_DIR=$HDF5_DIR"
elif command -v pkg-config >/dev/null && pkg-config --exists hdf5 2>/dev/null; then
    choice=system; why="pkg-config finds hdf5 $(pkg-config --modversion hdf5)"
else
    choice=bundled
    why="no system HDF5 (pkg-config finds none, HDF5_DIR unset) and no root to install one: built from its bundled sources and linked statically"
fi
if [ "${1:-}" = --why ]; then
    echo "HDF5: $choice ($why)"
else
    echo "$choice"
fi
