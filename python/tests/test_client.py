"""ddsimp.Client against a real ddsimp-server started by the test."""
import sys
import threading

import numpy as np
import pytest

import ddsimp

WAIT = 60  # seconds a test waits for the server's next event: a bound on a hang, not a speed


@pytest.fixture(scope="module")
def vectors(data):
    """A surface with fields that the server does not hold yet (it starts with SurfaceVectors
    as its sample)."""
    whole = ddsimp.read(data / "surfaces" / "SurfaceVectors.vtk")
    return ddsimp.simplify(whole, keep=0.9, strategy="vertex")


def connect(server, name="python-test"):
    return ddsimp.Client(server.address, token=server.token, name=name)


def next_event_of_kind(client, kind):
    while True:
        event = client.next_event(timeout=WAIT)
        assert event is not None, f"no {kind} event within {WAIT} s"
        if event.kind == kind:
            return event


def test_upload_list_and_levels_as_numpy_arrays(server, vectors):
    with connect(server) as client:
        assert client.connected
        stored = client.upload(vectors, name="vectors")
        assert len(stored.surface) == 64 and not stored.already_stored
        assert (stored.triangles, stored.vertices) == (len(vectors.triangles), len(vectors.points))
        listed = {s.surface: s for s in client.list()}
        info = listed[stored.surface]
        assert info.name == "vectors" and info.triangles == len(vectors.triangles)
        assert [f.name for f in info.fields] == list(vectors.fields)
        temp = next(f for f in info.fields if f.name == "Temp")
        assert temp.min == pytest.approx(vectors.fields["Temp"].min())
        assert temp.max == pytest.approx(vectors.fields["Temp"].max())

        levels = client.simplify(stored.surface, keep=[0.5, 0.2], alpha=0.5, strategy="vertex")
        assert [lv.keep for lv in levels] == pytest.approx([0.5, 0.2])
        for level, keep in zip(levels, [0.5, 0.2]):
            assert level.triangle_count == len(level.triangles) <= int(keep * len(vectors.triangles))
            assert level.target_reached
            assert level.points.dtype == np.float32 and level.triangles.dtype == np.uint32
            assert level.triangles.max() < len(level.points)
            assert list(level.fields) == list(vectors.fields)
            assert level.fields["V"].shape == (len(level.points), 3)
        assert len(levels[1].triangles) < len(levels[0].triangles)

        one = client.simplify(stored.surface, keep=0.2, strategy="vertex")
        assert one.cached and one.triangles.tobytes() == levels[1].triangles.tobytes()

        # Edge collapse's data placement travels: the library's level for the same options.
        interpolated = client.simplify(stored.surface, keep=0.2, alpha=0.0,
                                       data_placement="interpolated")
        local = ddsimp.simplify(vectors, keep=0.2, alpha=0.0, data_placement="interpolated")
        assert interpolated.points.tobytes() == local.points.tobytes()
        assert interpolated.fields["Temp"].tobytes() == local.fields["Temp"].tobytes()
        least_error = client.simplify(stored.surface, keep=0.2, alpha=0.0)
        assert least_error.fields["Temp"].tobytes() != interpolated.fields["Temp"].tobytes()

        assert client.delete(stored.surface)
        assert stored.surface not in {s.surface for s in client.list()}
        with pytest.raises(ddsimp.ClientError) as gone:
            client.delete(stored.surface)
        assert gone.value.code == "NOT_FOUND"


def test_server_refusals_are_client_errors_with_their_code(server, vectors):
    with connect(server) as client:
        with pytest.raises(ddsimp.ClientError) as missing:
            client.simplify("0" * 64, keep=0.5)
        assert missing.value.code == "NOT_FOUND"
        with pytest.raises(ddsimp.ClientError) as bad:
            client.upload(vectors.points, np.array([[0, 1, 999]]))
        assert bad.value.code in {"BAD_SURFACE", "INVALID_ARGUMENT"}
        assert "refers to vertex 999" in str(bad.value)
        assert all(s.triangles != 1 for s in client.list())
        # The connection goes on after a refusal.
        assert client.upload(vectors).triangles == len(vectors.triangles)


def test_a_wrong_token_or_no_server_cannot_connect(server):
    with pytest.raises(ddsimp.ClientError) as refused:
        ddsimp.Client(server.address, token="wrong")
    assert refused.value.code == "UNAUTHENTICATED"
    server.stop()
    with pytest.raises(ddsimp.ClientError) as gone:
        ddsimp.Client(server.address, token=server.token, timeout=5)
    assert gone.value.code == "CONNECTION"
    with pytest.raises(ValueError):
        ddsimp.Client("localhost:notaport")


def test_session_members_see_an_upload_and_a_view_change(server, vectors):
    with connect(server, "publisher") as publisher, connect(server, "viewer") as viewer:
        watching = viewer.watch("review", key="k1", timeout=WAIT)
        first = next(watching)
        assert first.kind == "state" and first.state.name == "review"
        publisher.join("review", key="k1")
        stored = publisher.upload(vectors, name="cut", session="review")
        mesh = None
        for event in watching:
            if event.kind == "mesh":
                mesh = event.mesh
                break
        assert mesh is not None, "the viewer saw no mesh"
        assert mesh.session == "review" and 0 < len(mesh.triangles) <= len(vectors.triangles)
        assert list(mesh.fields) == list(vectors.fields)

        state = publisher.set_view("review", keep=0.25, field="Temp")
        assert state.view.surface == stored.surface
        assert state.view.keep == pytest.approx(0.25) and state.view.field == "Temp"
        names = {m.name for m in state.members}
        assert {"publisher", "viewer"} <= names
        seen = next_event_of_kind(viewer, "state")
        while seen.state.cause != "view":
            seen = next_event_of_kind(viewer, "state")
        assert seen.state.view.keep == pytest.approx(0.25)


def test_a_session_with_another_key_does_not_see_it(server, vectors):
    with connect(server, "a") as a, connect(server, "b") as b:
        a.join("private", key="right")
        b.join("private", key="other")
        stored = a.upload(vectors, session="private")
        assert stored.surface not in {s.surface for s in b.list()}
        assert stored.surface in {s.surface for s in a.list()}


def test_waiting_for_an_event_lets_other_threads_run(server):
    """A thread waits for a session event that only this thread's join can cause: if the wait
    held the GIL, the join could not run and the wait would end empty."""
    with connect(server, "waiter") as waiter, connect(server, "joiner") as joiner:
        waiter.join("gil")
        assert next_event_of_kind(waiter, "state").state.cause in {"created", "joined"}
        got = []
        interval = sys.getswitchinterval()
        sys.setswitchinterval(1000)
        try:
            thread = threading.Thread(target=lambda: got.append(waiter.next_event(timeout=WAIT)))
            thread.start()
            joiner.join("gil")
            thread.join()
        finally:
            sys.setswitchinterval(interval)
        assert got[0] is not None and got[0].kind == "state"
        assert any(m.name == "joiner" for m in got[0].state.members)
