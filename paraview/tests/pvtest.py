"""Shared by the plugin's pvpython tests: ParaView's own Python modules first, the plugin loaded,
and the environment ctest sets (paraview/tests/CMakeLists.txt)."""
import os
import sys

# Where python3-paraview was unpacked beside the system's python3-vtk9 (scripts/install-deps.sh):
# its vtkmodules must come before the system's.
if os.environ.get("DDSIMP_PV_SITE"):
    sys.path.insert(0, os.environ["DDSIMP_PV_SITE"])

from paraview import servermanager  # noqa: E402
from paraview import simple  # noqa: E402


def required(name):
    value = os.environ.get(name)
    if not value:
        raise RuntimeError(f"{name} is not set (run these tests through ctest)")
    return value


def load_plugin(namespace):
    """Loads the plugin; its filters become functions in `namespace` (a test's globals())."""
    simple.LoadPlugin(required("DDSIMP_PLUGIN"), remote=False, ns=namespace)
    return simple


def fetch(proxy):
    """The proxy's output as a VTK object in this process."""
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy)


def field_value(poly, name):
    array = poly.GetFieldData().GetAbstractArray(name)
    assert array is not None, f"no field-data array {name}"
    return array.GetValue(0)
