#!/usr/bin/env bash
# Installs every Debian package rayunits needs. Idempotent: skips what is present.
# Usage: scripts/install-deps.sh [--long]   (--long adds the real-scene meshes, chromium for the report-page test
# and slurm-wlm + munge for the single-node Slurm test tests/sweep/slurm_e2e.sh)
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build ccache pkg-config git
  verilator yosys iverilog nextpnr-ice40 fpga-icestorm
  libsystemc-dev libgtest-dev libgmock-dev libbenchmark-dev
  libgmp-dev libmpfr-dev libfftw3-dev
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libstb-dev
  python3 python3-matplotlib python3-numpy libassimp-dev
  # NSGA-II of the datapath search (rayunits search, model/src/dp/search.cpp)
  libpagmo-dev
  # The cell-library flow (synth --flow osu018): the liberty, OpenSTA, ABC, and qflow's back
  # end for place and route (synth/pnr). --no-install-recommends: each is named.
  qflow-tech-osu018 qflow-tech-osu035 qflow-tech-osu050 opensta berkeley-abc
  qflow graywolf qrouter magic netgen-lvs xz-utils
)
if [[ "${1:-}" == "--long" ]]; then PKGS+=(assimp-testmodels libcgal-demo chromium slurm-wlm munge); fi
missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#PKGS[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "install-deps: error: not root and no sudo; install as root: apt-get install ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
