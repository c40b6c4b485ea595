"""Fixtures of the ddsimp package's tests: the shared data and a real ddsimp-server.

Environment (set by python/tests/CMakeLists.txt): PYTHONPATH (the built package),
DDSIMP_SHARED_DATA, DDSIMP_SERVER (the server binary), DDSIMP_CLI (the ddsimp command).
"""
import os
import pathlib
import socket
import subprocess
import time

import pytest


def _required(name):
    value = os.environ.get(name)
    if not value:
        raise RuntimeError(f"{name} is not set (run these tests through ctest)")
    return value


@pytest.fixture(scope="session")
def data():
    return pathlib.Path(_required("DDSIMP_SHARED_DATA"))


@pytest.fixture(scope="session")
def cli():
    return _required("DDSIMP_CLI")


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _accepts(port):
    with socket.socket() as s:
        return s.connect_ex(("127.0.0.1", port)) == 0


class Server:
    """A ddsimp-server child on free loopback ports, with a token."""

    token = "python-test-token"

    def __init__(self, data_dir):
        for _ in range(5):  # a port found free may be taken before the server binds it
            self.port, self.http_port = _free_port(), _free_port()
            self.process = subprocess.Popen(
                [_required("DDSIMP_SERVER"), "--port", str(self.port), "--http-port",
                 str(self.http_port), "--data-dir", str(data_dir), "--token", self.token,
                 "--log-level", "warn"])
            for _ in range(400):
                if _accepts(self.port) and _accepts(self.http_port):
                    return
                if self.process.poll() is not None:
                    break
                time.sleep(0.05)
            self.stop()
        raise RuntimeError("ddsimp-server did not start listening")

    @property
    def address(self):
        return f"127.0.0.1:{self.port}"

    def stop(self):
        if self.process.poll() is None:
            self.process.terminate()
            self.process.wait(timeout=30)


@pytest.fixture()
def server(tmp_path):
    s = Server(tmp_path / "server-data")
    yield s
    s.stop()
