#!/usr/bin/env bash
# The main job: install what is missing, build, and simplify the shipped sample surface
# (a cutting plane through a CVD reactor with temperature, pressure, velocity and species).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target ddsimp_cli

out=build/release/sample
mkdir -p "$out"
ddsimp=build/release/tools/ddsimp
"$ddsimp" info data/SurfaceVectors.vtk
for strategy in edge vertex; do
    "$ddsimp" simplify data/SurfaceVectors.vtk -o "$out/SurfaceVectors-$strategy-25.vtk" \
        --alpha 0.3 --keep 0.25 --strategy "$strategy" --json
    "$ddsimp" compare data/SurfaceVectors.vtk "$out/SurfaceVectors-$strategy-25.vtk" --field Temp
done
echo "reduced surfaces written to $out/"
