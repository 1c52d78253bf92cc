#!/usr/bin/env bash
# Installs the Debian packages this project builds and runs with.
# Idempotent: it asks dpkg first and calls apt-get only for what is missing,
# so a second run costs a fraction of a second.
set -euo pipefail

packages=(
  cmake g++ make pkg-config
  clang libclang-rt-14-dev clang-tidy
  libeigen3-dev
  libboost-dev
  libprotobuf-dev protobuf-compiler
  libspdlog-dev
  libgtest-dev libgmock-dev
  libbenchmark-dev
  libtomlplusplus-dev
  libcli11-dev
  python3 python3-matplotlib python3-protobuf python3-numpy
  python3-dolfinx   # the finite-element soil (fe_soil/): FEniCSx with PETSc and MPI
  python3-scipy     # the soil from Green's functions (green_soil/): Bessel functions, quadrature
  iproute2
  parallel          # runs a study plan (master study --plan), and its test
  libzip-dev        # the FMU host (fmu/): unpacks a .fmu archive; the test FMUs are packed with it
  libpugixml-dev    # the FMU host (fmu/): reads an FMU's modelDescription.xml
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null; then
    sudo_cmd=(sudo)
  else
    echo "install-deps: missing packages (${missing[*]}) and not root; run as root or install them" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
