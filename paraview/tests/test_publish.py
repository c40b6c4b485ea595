"""pvpython, headless: PublishToSession uploads into a session of a real ddsimp-server, and
another member of that session (a renderer) receives the surface with its fields."""
import os
import socket
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pvtest  # noqa: E402  (sets up ParaView's modules first)

simple = pvtest.load_plugin(globals())
data = pvtest.required("DDSIMP_SHARED_DATA")
TOKEN = "paraview-test-token"
WAIT = 60  # seconds: a bound on a hang, not a speed


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def accepts(port):
    with socket.socket() as s:
        return s.connect_ex(("127.0.0.1", port)) == 0


def start_server(data_dir):
    for _ in range(5):  # a port found free may be taken before the server binds it
        port, http_port = free_port(), free_port()
        server = subprocess.Popen([pvtest.required("DDSIMP_SERVER"), "--port", str(port),
                                   "--http-port", str(http_port), "--data-dir", data_dir,
                                   "--token", TOKEN, "--log-level", "warn"])
        for _ in range(400):
            if accepts(port) and accepts(http_port):
                return server, port
            if server.poll() is not None:
                break
            time.sleep(0.05)
        server.kill()
        server.wait()
    raise RuntimeError("ddsimp-server did not start listening")


with tempfile.TemporaryDirectory() as data_dir:
    server, port = start_server(data_dir)
    address = f"127.0.0.1:{port}"
    try:
        watcher = subprocess.Popen([pvtest.required("DDSIMP_SESSION_WATCH"), address, TOKEN,
                                    "review", "k1", str(WAIT)], stdout=subprocess.PIPE, text=True)
        assert watcher.stdout.readline().strip() == "joined"

        vectors = simple.ExtractSurface(Input=simple.LegacyVTKReader(
            FileNames=[os.path.join(data, "surfaces", "SurfaceVectors.vtk")]))
        decimated = DataDependentDecimation(Input=vectors, Keep=0.5)
        publish = PublishToSession(Input=decimated, Server=address, Token=TOKEN,
                                          Session="review", Key="k1", Name="from-paraview")
        out = pvtest.fetch(publish)
        status = pvtest.field_value(out, "PublishStatus")
        assert status.startswith(f"published to {address}, session review"), status
        surface_id = pvtest.field_value(out, "PublishedSurface")
        assert len(surface_id) == 64 and all(c in "0123456789abcdef" for c in surface_id)
        # The filter passes its input through, with the decimation's report.
        assert out.GetNumberOfPolys() <= 756 // 2
        assert pvtest.field_value(out, "TargetReached") == 1

        line, _ = watcher.communicate(timeout=WAIT + 30)
        assert watcher.returncode == 0, "the session member saw no mesh"
        seen = dict(item.split("=", 1) for item in line.split()[1:])
        assert int(seen["triangles"]) == out.GetNumberOfPolys(), (seen, out.GetNumberOfPolys())
        assert int(seen["vertices"]) == out.GetNumberOfPoints()
        pd = out.GetPointData()
        expected = [f"{pd.GetArrayName(i)}:{pd.GetArray(i).GetNumberOfComponents()}"
                    for i in range(pd.GetNumberOfArrays())]
        assert seen["fields"].split(",") == expected, (seen["fields"], expected)

        # A wrong token: no upload, the reason in the status, the data still passes through.
        publish.Token = "wrong"
        out = pvtest.fetch(publish)
        assert pvtest.field_value(out, "PublishedSurface") == ""
        status = pvtest.field_value(out, "PublishStatus")
        assert status.startswith("not published: "), status
        assert out.GetNumberOfPolys() > 0

        # Without a session nothing is published.
        publish.Token = TOKEN
        publish.Session = ""
        out = pvtest.fetch(publish)
        assert pvtest.field_value(out, "PublishStatus") == "not published: set Server and Session"
    finally:
        server.terminate()
        server.wait(timeout=30)
print("publish: all checks passed")
