"""A scheduler address of the wrong protocol is refused within seconds, saying that a Dask
scheduler speaks tcp:// and what answered there (issue 33, item 8: an http:// address ended in a
TimeoutError after 20 s)."""

import http.server
import socket
import threading
import time

import pytest

from saggriac import Config, Study, run_study
from saggriac.errors import ParameterError

pytest.importorskip("distributed")


@pytest.fixture
def web_server():
    """A web server on a free port of this machine, for the time of one test."""
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), http.server.SimpleHTTPRequestHandler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield server.server_address[1]
    server.shutdown()
    server.server_close()


def _study():
    return Study(Config.from_preset("exp1", n_steps=300, n_evals=1), ("sagg_riac",), (0,))


def test_an_http_address_names_the_protocol_and_what_answered(web_server, tmp_path):
    t = time.perf_counter()
    with pytest.raises(ParameterError, match=r"speaks Dask's own protocol over tcp://.*web server answers 'HTTP/1.0 200 OK', server 'SimpleHTTP") as e:
        run_study(_study(), tmp_path / "st", backend="dask", scheduler=f"http://127.0.0.1:{web_server}", progress=False)
    assert time.perf_counter() - t < 5
    assert e.value.param == "scheduler"
    assert not (tmp_path / "st").exists()


def test_an_http_address_where_nothing_listens_says_so(tmp_path):
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    # The port is free again once the socket is closed: nothing answers there.
    with pytest.raises(ParameterError, match=rf"tcp://.*nothing answers at 127.0.0.1:{port}"):
        run_study(_study(), tmp_path / "st", backend="dask", scheduler=f"http://127.0.0.1:{port}/status", progress=False)
