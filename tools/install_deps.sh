#!/usr/bin/env bash
# Install the Debian packages geoblock needs, if any is missing.
# Uses apt-get directly as root, through sudo otherwise.
set -euo pipefail
pkgs="gfortran make libopenmpi-dev openmpi-bin libhypre-dev libmetis-dev libmumps-dev
      libhdf5-openmpi-dev liblapack-dev libopenblas-dev python3 python3-numpy python3-h5py
      python3-matplotlib python3-meshio python3-petsc4py bc time"
missing=""
for p in $pkgs; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing="$missing $p"
  fi
done
[ -z "$missing" ] && exit 0
echo "geoblock: installing Debian packages:$missing"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends $missing
