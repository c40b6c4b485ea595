#!/usr/bin/env bash
# Makes the fidelity report's surfaces from every data set in ../shared/data (see its README):
# isosurfaces of the volumes with `ddsimp isosurface` (the named fields carried), cutting planes
# through two volumes, the ready surfaces as they are (the OpenFOAM plane's two files merged), and
# the three data-less geometries with a derived scalar `heat`. Each surface keeps at most one
# scalar and one 3-vector field: the attributes vtkQuadricDecimation's error metric can weigh.
# Every surface is repaired by ddsimp::validate once here, so all simplifiers get the same input.
#
# Usage: bench/report/make-surfaces.sh BUILD_DIR OUT_DIR [--quick | --scaling | --held-out]
#   --quick     only the two small surfaces of the smoke test
#   --scaling   the carotid isosurfaces of growing size for the time-against-size plot
#   --held-out  isosurfaces of the report's volumes at other values (held_out.py)
# Files that exist are kept (delete them to remake).
set -euo pipefail

if (($# < 2)); then
    echo "usage: make-surfaces.sh BUILD_DIR OUT_DIR [--quick | --scaling | --held-out]" >&2
    exit 2
fi
build=$1 out=$2 mode=${3:-full}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$(dirname "$here")")
shared="${DDSIMP_SHARED_DATA:-$(cd "$root/.." && pwd)/shared/data}"
ddsimp="$build/tools/ddsimp"
report="$build/bench/report/ddsimp_report"
mkdir -p "$out"

# iso NAME VOLUME ARGS...: an isosurface (through a temporary file: no half-written surface).
iso() {
    local name=$1 volume=$2
    shift 2
    [[ -f "$out/$name.vtp" ]] && return
    "$ddsimp" isosurface "$shared/volumes/$volume" "$@" -o "$out/$name.raw.vtp" >/dev/null
    "$report" prepare "$out/$name.raw.vtp" -o "$out/$name.partial.vtp"
    rm -f "$out/$name.raw.vtp"
    mv "$out/$name.partial.vtp" "$out/$name.vtp"
}
# cut NAME VOLUME ARGS...: a cutting plane.
cut() {
    local name=$1 volume=$2
    shift 2
    [[ -f "$out/$name.vtp" ]] && return
    "$report" cut "$shared/volumes/$volume" "$@" -o "$out/$name.partial.vtp"
    mv "$out/$name.partial.vtp" "$out/$name.vtp"
}
# ready NAME ARGS...: a ready surface (prepare's arguments).
ready() {
    local name=$1
    shift
    [[ -f "$out/$name.vtp" ]] && return
    "$report" prepare "$@" -o "$out/$name.partial.vtp"
    mv "$out/$name.partial.vtp" "$out/$name.vtp"
}

case "$mode" in
--quick)
    ready disk-cut "$shared/surfaces/SurfaceVectors.vtk" --fields Temp,V
    iso disk-temp400 disk_out_ref.ex2 --field Temp --value 400 --carry Pres,V
    ;;
full)
    ready disk-cut "$shared/surfaces/SurfaceVectors.vtk" --fields Temp,V
    iso disk-temp400 disk_out_ref.ex2 --field Temp --value 400 --carry Pres,V
    iso combustor-density combxyz.bin --q "$shared/volumes/combq.bin" --function 153 \
        --field Density --value 0.24 --carry VelocityMagnitude,Momentum
    iso bluntfin-density bluntfinxyz.bin --q "$shared/volumes/bluntfinq.bin" --function 110 \
        --field Density --value 0.89 --carry Pressure,Momentum
    iso kitchen-h1 kitchen.vtk --field h1 --value 20750 --carry p1,velocity
    iso fire-t450 fire_ug.vtu --field t --value 450 --carry mfrac,uvw
    cut fire-cut fire_ug.vtu --axis y --at 0.5 --fields t,uvw
    iso carotid-175 carotid.vtk --field scalars --value 175 --carry vectors
    iso cth-armor cth.vtr --field "Volume Fraction for Armor Plate" --value 0.5 --carry Pressure
    cut cth-cut cth.vtr --axis z --at 0.5 --fields Pressure
    ready earth "$shared/surfaces/earth.vtp" --fields bottomDepth
    ready motorbike-y0 "$shared/surfaces/motorBike_cuttingPlane_500/p_yNormal.vtk" \
        "$shared/surfaces/motorBike_cuttingPlane_500/U_yNormal.vtk" --fields p,U
    ready bunny "$shared/geometry/bunny.ply" --derive-heat
    ready armadillo "$shared/geometry/armadillo.off" --derive-heat
    ready fandisk "$shared/geometry/fandisk.off" --derive-heat
    # The >= 1 M-triangle surface: the resampled carotid of bench/make-data.sh.
    iso carotid-1m carotid.vtk --field scalars --value 127 --resample 3 --carry vectors
    ;;
--scaling)
    iso scale-carotid-r1-175 carotid.vtk --field scalars --value 175 --carry vectors
    iso scale-carotid-r1 carotid.vtk --field scalars --value 127 --carry vectors
    iso scale-carotid-r2 carotid.vtk --field scalars --value 127 --resample 2 --carry vectors
    iso scale-carotid-r3 carotid.vtk --field scalars --value 127 --resample 3 --carry vectors
    iso scale-carotid-r6 carotid.vtk --field scalars --value 127 --resample 6 --carry vectors
    ;;
--held-out)
    # The report's volumes at other values (held_out.py): what a change tuned to the report's
    # own surfaces would miss.
    iso disk-temp350 disk_out_ref.ex2 --field Temp --value 350 --carry Pres,V
    iso disk-temp500 disk_out_ref.ex2 --field Temp --value 500 --carry Pres,V
    iso combustor-density30 combxyz.bin --q "$shared/volumes/combq.bin" --function 153 \
        --field Density --value 0.30 --carry VelocityMagnitude,Momentum
    iso bluntfin-density11 bluntfinxyz.bin --q "$shared/volumes/bluntfinq.bin" --function 110 \
        --field Density --value 1.1 --carry Pressure,Momentum
    iso kitchen-h20600 kitchen.vtk --field h1 --value 20600 --carry p1,velocity
    iso fire-t400 fire_ug.vtu --field t --value 400 --carry mfrac,uvw
    iso carotid-150 carotid.vtk --field scalars --value 150 --carry vectors
    iso cth-armor03 cth.vtr --field "Volume Fraction for Armor Plate" --value 0.3 --carry Pressure
    # ... and at other values again, each carrying one field of its volume.
    iso disk-temp300 disk_out_ref.ex2 --field Temp --value 300 --carry Pres
    iso disk-temp420 disk_out_ref.ex2 --field Temp --value 420 --carry V
    iso fire-t350 fire_ug.vtu --field t --value 350 --carry uvw
    iso kitchen-h20400 kitchen.vtk --field h1 --value 20400 --carry velocity
    iso bluntfin-density09 bluntfinxyz.bin --q "$shared/volumes/bluntfinq.bin" --field Density \
        --value 0.9 --carry Momentum
    iso combustor-density22 combxyz.bin --q "$shared/volumes/combq.bin" --field Density \
        --value 0.22 --carry Momentum
    iso cth-armor07 cth.vtr --field "Volume Fraction for Armor Plate" --value 0.7 --carry Pressure
    iso carotid-120 carotid.vtk --field scalars --value 120 --carry vectors
    ;;
*)
    echo "make-surfaces.sh: unknown mode $mode" >&2
    exit 2
    ;;
esac
