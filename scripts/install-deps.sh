#!/usr/bin/env bash
# Installs the Debian packages ddsimp builds against, if any is missing.
set -euo pipefail

packages=(
    build-essential cmake ninja-build pkg-config
    libopenmesh-dev libvtk9-dev libcli11-dev nlohmann-json3-dev
    libmeshoptimizer-dev libgtest-dev libgmock-dev libbenchmark-dev jq
    libtbb-dev  # oneTBB: the engine's parallel loops
    libboost-dev libprotobuf-dev protobuf-compiler libspdlog-dev libssl-dev
    openmpi-bin libopenmpi-dev
    yamllint shellcheck
    iproute2 procps  # the Slurm job finds free ports with ss; its test stops the server with pkill
    clang libclang-rt-14-dev llvm  # tests/fuzz/run.sh: libFuzzer and llvm-symbolizer
    python3-matplotlib python3-vtk9 xvfb xauth
    pybind11-dev python3-dev python3-numpy python3-pytest  # python/: the ddsimp package and its tests
    paraview-dev  # paraview/: the plugin (ParaView 5.11 with its own VTK)
    chromium  # tests/web: the browser renderer's end-to-end tests (headless)
)

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js and npm build the browser renderer (web/). Node.js may come from elsewhere already
# (NodeSource's nodejs bundles npm and conflicts with Debian's npm package).
command -v node >/dev/null || missing+=(nodejs)
command -v npm >/dev/null || missing+=(npm)
sudo=""
[[ $(id -u) -ne 0 ]] && sudo="sudo"
if [[ ${#missing[@]} -gt 0 ]]; then
    echo "installing: ${missing[*]}"
    $sudo apt-get update -q
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# pvpython, for the ParaView plugin's tests, is in python3-paraview, which conflicts with
# python3-vtk9 (libvtk9-dev needs it): the package of the installed ParaView's version is
# unpacked beside the system instead (paraview/tests/CMakeLists.txt looks there).
pvpython_root=/opt/ddsimp/python3-paraview
if [[ ! -x $pvpython_root/usr/bin/pvpython ]] && ! command -v pvpython >/dev/null; then
    version=$(dpkg-query -W -f='${Version}' paraview)
    download=$(mktemp -d)
    (cd "$download" && apt-get download -q "python3-paraview=$version")
    $sudo mkdir -p "$pvpython_root"
    $sudo dpkg-deb -x "$download"/python3-paraview_*.deb "$pvpython_root"
    rm -rf "$download"
fi
