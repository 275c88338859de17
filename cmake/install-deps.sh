#!/usr/bin/env bash
# Installs the Debian packages this project builds and runs on. Idempotent:
# packages already present are left alone and apt-get is not called at all.
# Nothing is fetched from anywhere but Debian's archive.
set -euo pipefail

packages=(
  build-essential cmake ccache pkg-config
  trilinos-all-dev libptscotch-dev libscotch-dev   # Tpetra, Anasazi, Amesos2, Belos, Teuchos
  libopenmpi-dev openmpi-bin                        # MPI (Trilinos is built against Open MPI)
  libhwloc-dev                                      # hwloc, as Open MPI loads it (the process-start test)
  libsuitesparse-dev                                # CHOLMOD
  libmumps-dev                                      # MUMPS: distributed factorisations
  libarpack2-dev libparpack2-dev                    # ARPACK and its MPI version PARPACK
  libgtest-dev                                      # GoogleTest
  gmsh libgmsh-dev                                  # meshes: the Gmsh SDK and command
  calculix-ccx                                      # a peer FE code to compare with (benchmarks)
  python3-matplotlib                                # plots of the cms driver (--plot)
  python3-vtk9                                      # reading the mode-shape files back in a test
  nlohmann-json3-dev                                # JSON results (packages/io)
  libyaml-cpp-dev                                   # YAML scenes (packages/scene)
  liblapack-dev libblas-dev libopenblas0-pthread   # optimised BLAS/LAPACK through Debian's alternatives
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
