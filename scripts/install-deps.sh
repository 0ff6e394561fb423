#!/usr/bin/env bash
# Install the Debian 12 packages nct needs to build, run and test.
# Idempotent: does nothing when every package is already present.
set -euo pipefail

packages=(
  # build
  cmake g++ make pkg-config
  # FEniCSx 0.5 (dolfinx C++ library, the form compiler and its Python stack)
  libdolfinx-dev python3-dolfinx python3-ffcx python3-basix python3-ufl libbasix-dev
  # meshing
  gmsh python3-gmsh libgmsh-dev
  # MPI and an optimised BLAS for MUMPS (the reference BLAS is 8-15x slower)
  openmpi-bin libopenmpi-dev libopenblas0
  # scene files, command line, JSON, tests
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev googletest libgtest-dev
  # study statistics (Boost.Math: the F distribution); fits (Ceres:
  # Levenberg-Marquardt with bounds, covariance)
  libboost-dev libceres-dev
  # scripts and test checks (read XDMF/HDF5, plots)
  python3-numpy python3-h5py python3-matplotlib
  # Slurm and munge: studies and fits as job arrays on a cluster, and the
  # tests' single-node cluster (scripts/slurm-cluster.sh); no daemon is
  # started by the install
  slurmctld slurmd slurm-client munge
  # the study test's independent ANOVA (least squares, F tests); the
  # checkpoint test's matching of points across partitions (k-d tree) and
  # its XPath look-ups in the XDMF files
  python3-scipy python3-lxml
  # emulators: Gaussian processes (scikit-learn's GaussianProcessRegressor)
  python3-sklearn
  # the report pages' browser test: headless Chromium driven by Selenium
  # (tests/report_pages.py)
  chromium chromium-driver python3-selenium
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
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
