#!/usr/bin/env bash
# Set-up, build and run for AdaptiveRedistribution on Debian bookworm.
#
#   bash Plugin/Scripts/setup.sh run    # install what is missing, build, run the pipeline on the bundled data
#   bash Plugin/Scripts/setup.sh run SOLUTION...   # ... or adapt these solutions in one step (AdaptToShocks)
#   bash Plugin/Scripts/setup.sh test   # install what is missing, build, run every test (ctest)
#
# Environment: AR_BUILD_DIR (default <repo>/build), AR_OUTPUT_DIR (default
# <repo>/AdaptiveRedistribution-output), AR_JOBS (build jobs, default nproc).
set -euo pipefail

mode="${1:-}"
shift || true
inputs=()
for f in "$@"; do inputs+=("$(cd "$(dirname "$f")" && pwd)/$(basename "$f")"); done
if [[ "$mode" != "run" && "$mode" != "test" ]]; then
  echo "usage: bash Plugin/Scripts/setup.sh run|test" >&2
  exit 2
fi

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${AR_BUILD_DIR:-$root/build}"
output="${AR_OUTPUT_DIR:-$root/AdaptiveRedistribution-output}"
jobs="${AR_JOBS:-$(nproc)}"

# Everything the build, the tests and the pictures need, one line per group
# (the README's set-up section says the same). The ParaView SDK's CMake
# configuration asks for the -dev packages of what ParaView was built with.
packages=(
  # the build tools
  git cmake ninja-build g++ make ca-certificates pkg-config
  # ParaView (pvpython, pvbatch, pvserver, the GUI) and its SDK, numpy and matplotlib for the scripts
  paraview paraview-dev python3-paraview python3-numpy python3-matplotlib
  # the core's libraries: CGAL, TetGen (library and program), Eigen, Boost; GoogleTest
  libcgal-dev libgmp-dev libmpfr-dev libtet1.5-dev tetgen libeigen3-dev libboost-dev libgtest-dev
  # the programs the tests and data scripts call: gmsh (reads back our .msh, meshes the analytic
  # cases), OpenFOAM v1912 (gmshToFoam, checkMesh, blockMesh, the solvers) and its tutorials
  gmsh openfoam openfoam-examples
  # the rest of the ParaView SDK's configuration (Qt, VTK's third-party libraries, MPI, X)
  qtbase5-dev qttools5-dev libqt5svg5-dev libqt5x11extras5-dev qtxmlpatterns5-dev-tools
  libutfcpp-dev libdouble-conversion-dev libgl2ps-dev libglew-dev libnetcdf-dev libhdf5-openmpi-dev
  libavformat-dev libavcodec-dev libswscale-dev libavutil-dev libtheora-dev liblz4-dev liblzma-dev
  libxml2-dev libtiff-dev libjpeg-dev libpng-dev libfreetype-dev libexpat1-dev
  mpi-default-dev mpi-default-bin python3-mpi4py
  libx11-dev libgl-dev libxt-dev libpugixml-dev libjsoncpp-dev libfmt-dev libprotobuf-dev protobuf-compiler
  libcgns-dev libexodusii-dev
  # a virtual display for pvbatch's pictures and the GUI tests; xdotool and ImageMagick's import
  # drive the real paraview GUI and take its screenshot (GUIAdaptToShocks)
  xvfb xauth xdotool imagemagick
)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} > 0)); then
  echo "== installing ${#missing[@]} missing Debian packages: ${missing[*]}"
  sudo=""
  if [[ "$(id -u)" != "0" ]]; then sudo="sudo"; fi
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
fi

echo "== configuring and building in $build"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j "$jobs"
plugin="$build/lib/paraview-5.11/plugins/AdaptiveRedistribution/AdaptiveRedistribution.so"
echo "== plugin: $plugin"

# pvbatch renders through X: use a virtual display when there is none.
# -noreset: by default Xvfb resets when its last client leaves, and drops a
# client that connected meanwhile (its XOpenDisplay fails: VTK aborts with
# "bad X server connection"); VTK opens and closes connections in quick
# succession, so about one run in three of the main job died that way.
x=()
if [[ -z "${DISPLAY:-}" ]]; then x=(xvfb-run -a -s "-screen 0 1600x1200x24 -noreset"); fi

if [[ "$mode" == "run" ]]; then
  mkdir -p "$output"
  extra=()
  if ((${#inputs[@]} > 0)); then extra=(--input "${inputs[@]}"); fi
  "${x[@]}" pvbatch "$root/Plugin/Scripts/run_pipeline.py" --plugin "$plugin" --data "$root/Data" --output "$output" "${extra[@]}"
  echo "== outputs in $output"
else
  cd "$build"
  "${x[@]}" ctest --output-on-failure
fi
