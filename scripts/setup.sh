#!/bin/bash
# setup.sh: install what accelbench needs from Debian 12's packages (when
# missing) and build it with meson/ninja into build/. Safe to re-run: apt is
# skipped when every package is present, meson reconfigures in place.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
    gcc g++ libc6-dev pkg-config git meson ninja-build # toolchain (C, and C++ for the CGAL parts)
    libembree-dev                                      # Embree 3: reference and speed bar
    libcgal-dev libgmp-dev libmpfr-dev                 # CGAL: the exact judge of verify and the cgal-aabb peer
    libassimp-dev libarchive-dev libpng-dev            # mesh loading, compressed files, PNG output
    python3-matplotlib python3-numpy                   # plots from the CSV, the report's fits (scripts/report.py)
    chromium                                           # the report's browser test (tests/test_report_browser.sh)
    libcgal-demo glmark2-data occt-misc openfoam-examples  # benchmark meshes (bunny, dragon, head, motorbike ...)
    slurmctld slurmd slurm-client munge                # a single-node Slurm for tests/test_slurm.sh (scripts/slurm/)
)

missing=()
for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}"
    SUDO=""
    [ "$(id -u)" = 0 ] || SUDO=sudo
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" > /dev/null
fi

if [ -f build/build.ninja ]; then
    meson setup --reconfigure build > /dev/null
else
    meson setup build --buildtype=release > /dev/null
fi
ninja -C build > /dev/null
echo "setup: built build/harness/accelbench ($(build/harness/accelbench version))"
