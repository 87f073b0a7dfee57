"""A tcp:// address where no Dask scheduler answers is refused within seconds, naming what
answers there (issue 44, item 7): a peer that accepts and stays silent hung run_study for ever
inside distributed.Client, and an HTTP reply ended in "MemoryError: 3.07 EiB". A scheduler that
is not an address or a cluster (42) is refused by saggriac, not by Dask's TypeError."""

import logging
import socket
import threading
import time

import pytest

from saggriac import Config, Study, run_study
from saggriac.errors import ParameterError
from saggriac.study import backends

distributed = pytest.importorskip("distributed")

#: What each refusal must take at most; without the probe, the silent peer hangs for ever.
BOUND = backends.GREETING_TIMEOUT + backends.PROBE_TIMEOUT + 10


def _study():
    return Study(Config.from_preset("exp1", n_steps=300, n_evals=1), ("sagg_riac",), (0,))


def _listener(serve):
    """A socket on a free loopback port whose connections ``serve(conn)`` handles, in a thread."""
    server = socket.create_server(("127.0.0.1", 0))
    held = []

    def loop():
        while True:
            try:
                conn, _ = server.accept()
            except OSError:  # closed by the finalizer
                return
            held.append(conn)
            threading.Thread(target=serve, args=(conn,), daemon=True).start()

    threading.Thread(target=loop, daemon=True).start()
    return server, held


@pytest.fixture
def listener():
    opened = []

    def start(serve):
        server, held = _listener(serve)
        opened.append((server, held))
        return server.getsockname()[1]

    yield start
    for server, held in opened:
        server.close()
        for conn in held:
            conn.close()


def _silent(conn):
    pass  # accepts, says nothing, keeps the connection open until the test ends


def _bad_request(conn):
    # An HTTP server (or proxy) answering whatever it is sent, as one would a Dask handshake.
    conn.settimeout(10)
    try:
        conn.recv(4096)
        conn.sendall(b"HTTP/1.1 400 Bad Request\r\nServer: test-proxy\r\nContent-Length: 0\r\nConnection: close\r\n\r\n")
    except OSError:
        pass
    conn.close()


def _within(seconds, work):
    """``work()``'s exception, which must come within ``seconds``: a hang fails the test instead
    of the suite (the thread is a daemon and is left behind)."""
    outcome = {}

    def run():
        try:
            work()
        except BaseException as e:  # noqa: BLE001 - handed to the test
            outcome["error"] = e

    t0 = time.perf_counter()
    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    thread.join(seconds)
    assert not thread.is_alive(), f"run_study had not returned after {seconds} s"
    return outcome.get("error"), time.perf_counter() - t0


def test_a_silent_peer_is_refused_in_bounded_time(listener, tmp_path):
    port = listener(_silent)
    e, took = _within(BOUND, lambda: run_study(_study(), tmp_path / "st", backend="dask", scheduler=f"tcp://127.0.0.1:{port}", progress=False))
    assert isinstance(e, ParameterError), repr(e)
    assert e.param == "scheduler" and f"tcp://127.0.0.1:{port}" in str(e)
    assert f"said nothing in {backends.GREETING_TIMEOUT + backends.PROBE_TIMEOUT:g} s (a Dask scheduler greets at once)" in str(e)
    assert took < BOUND and not (tmp_path / "st").exists()


def test_an_http_reply_is_named_not_a_memory_error(listener, tmp_path):
    port = listener(_bad_request)
    e, _ = _within(BOUND, lambda: run_study(_study(), tmp_path / "st", backend="dask", scheduler=f"127.0.0.1:{port}", progress=False))
    assert isinstance(e, ParameterError), repr(e)
    assert "an HTTP server answers there (it replied 'HTTP/1.1 400 Bad Request', server 'test-proxy'), perhaps a Dask dashboard" in str(e)
    assert "8786" in str(e) and not (tmp_path / "st").exists()


def test_a_peer_speaking_another_protocol_is_named(listener, tmp_path):
    def ssh(conn):
        conn.sendall(b"SSH-2.0-OpenSSH_9.6\r\n")

    port = listener(ssh)
    e, _ = _within(BOUND, lambda: run_study(_study(), tmp_path / "st", backend="dask", scheduler=f"tcp://127.0.0.1:{port}", progress=False))
    assert isinstance(e, ParameterError) and "does not speak Dask's protocol (it sent b'SSH-2.0-OpenSSH_9.6" in str(e), repr(e)


@pytest.mark.parametrize("scheduler", [42, 8786.0, b"tcp://127.0.0.1:8786", ["tcp://127.0.0.1:8786"]])
def test_a_scheduler_that_is_neither_an_address_nor_a_cluster_is_refused(scheduler, tmp_path):
    with pytest.raises(ParameterError, match=r"'scheduler' parameter of run_study must be a Dask scheduler's address \(a str .*a distributed.Client, or a cluster object") as e:
        run_study(_study(), tmp_path / "st", backend="dask", scheduler=scheduler, progress=False)
    assert e.value.param == "scheduler" and e.value.value == repr(scheduler)
    assert f"Got {scheduler!r} instead" in str(e.value) and not (tmp_path / "st").exists()


def test_a_real_scheduler_passes_the_probe_without_a_word_in_its_log(caplog):
    # The probe hands the scheduler's greeting back as its handshake: no "closed before handshake".
    with distributed.LocalCluster(n_workers=0, processes=False, protocol="tcp", host="127.0.0.1", dashboard_address=None) as cluster:
        with caplog.at_level(logging.DEBUG, logger="distributed"):
            t0 = time.perf_counter()
            backends.check_scheduler(cluster.scheduler_address)
            assert time.perf_counter() - t0 < backends.GREETING_TIMEOUT
            time.sleep(0.5)  # the scheduler's side of the closed connection
        assert not [r for r in caplog.records if r.levelno >= logging.INFO and "handshake" in r.getMessage()]


def test_a_real_dashboard_given_as_tcp_is_named(tmp_path):
    # The usual slip: the dashboard's port (8787) where the scheduler's (8786) belongs.
    with distributed.LocalCluster(n_workers=0, processes=False, protocol="tcp", host="127.0.0.1", dashboard_address="127.0.0.1:0") as cluster:
        port = cluster.scheduler.http_server.port
        e, took = _within(BOUND, lambda: run_study(_study(), tmp_path / "st", backend="dask", scheduler=f"tcp://127.0.0.1:{port}", progress=False))
    assert isinstance(e, ParameterError), repr(e)
    assert "an HTTP server answers there (it replied 'HTTP/1.1" in str(e) and "server 'TornadoServer" in str(e) and "perhaps a Dask dashboard" in str(e)
    assert took < BOUND
