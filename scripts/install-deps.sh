#!/usr/bin/env bash
# Installs the Debian packages this project builds and runs with, by profile:
# the list of every profile is here and nowhere else.
#
#   scripts/install-deps.sh [--fe] [--green] [--tests] [--all] [--list]
#
#   (none)    the base: what scripts/run-main.sh needs to build the programs
#             and run the paper study (master study, its figures), the C++
#             package and the Python SDK
#   --fe      adds the FE soil's stack (fe_soil/): FEniCSx with PETSc and MPI
#   --green   adds the soil from Green's functions (green_soil/): scipy
#   --tests   adds what only the test suite uses: clang and its sanitizer
#             runtime, clang-tidy, GoogleTest/GoogleMock, GNU parallel,
#             iproute2 (network namespaces)
#   --all     every profile (scripts/run-tests.sh)
#   --list    print the packages of the profiles given, one a line, and stop
#
# Idempotent: it asks dpkg first and calls apt-get only for what is missing,
# so a second run costs a fraction of a second.
set -euo pipefail

base=(
  cmake g++ make pkg-config
  libeigen3-dev
  libboost-dev
  libprotobuf-dev protobuf-compiler
  libspdlog-dev
  libbenchmark-dev  # scripts/run-main.sh builds the benchmarks beside the programs
  libtomlplusplus-dev
  libcli11-dev
  libzip-dev libpugixml-dev  # FMUs as participants: the archive and its modelDescription.xml
  libspectra-dev    # the verdict's Arnoldi method on Eigen (master/verdict/)
  liblapack-dev     # the verdict's dense eigenvalues (multishift QR, master/verdict/)
  python3 python3-matplotlib python3-protobuf python3-numpy
)
fe=(
  python3-dolfinx   # the finite-element soil (fe_soil/): FEniCSx with PETSc and MPI
)
green=(
  python3-scipy     # the soil from Green's functions (green_soil/): Bessel functions, quadrature
)
tests=(
  clang libclang-rt-14-dev clang-tidy  # the sanitizer build and clang-tidy of run-tests.sh
  libgtest-dev libgmock-dev
  iproute2          # the tests across network namespaces
  parallel          # runs a study plan (master study --plan), and its test
)

packages=("${base[@]}")
list=0
for arg in "$@"; do
  case "$arg" in
    --fe) packages+=("${fe[@]}") ;;
    --green) packages+=("${green[@]}") ;;
    --tests) packages+=("${tests[@]}") ;;
    --all) packages+=("${fe[@]}" "${green[@]}" "${tests[@]}") ;;
    --list) list=1 ;;
    *)
      echo "install-deps: unknown option $arg (expected --fe, --green, --tests, --all or --list)" >&2
      exit 2
      ;;
  esac
done
mapfile -t packages < <(printf '%s\n' "${packages[@]}" | awk '!seen[$0]++')

if ((list)); then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

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
