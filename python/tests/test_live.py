"""vlpground.live() on loopback, fed by the simulator's UDP emitter (vlpground sim --udp)."""
from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import vlpground
from conftest import free_udp_port


@pytest.fixture
def ports():
    data, position = free_udp_port(), free_udp_port()
    while position == data:
        position = free_udp_port()
    return data, position


def test_live_frames_from_the_simulator(cli, ports):
    data, position = ports
    reader = vlpground.live(data, "127.0.0.1", position_port=position, frames=5, timeout_s=20)
    sender = subprocess.Popen(
        [str(cli), "sim", "urban", "--frames", "4", "--udp", f"127.0.0.1:{data}",
         "--position-port", str(position), "--rate", "2", "--loop"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        frames = list(reader)
    finally:
        sender.terminate()
        sender.wait(timeout=10)
    assert len(frames) == 5 and reader.frames == 5
    assert [f.meta.sequence for f in frames] == list(range(5))
    complete = [f for f in frames if f.meta.complete]
    assert len(complete) >= 3
    for f in complete:
        assert 1500 < f.columns < 2000  # 600 rpm: about 1808 firing sequences
        assert f.ground_returns > 0.2 * f.returns and (f.label[f.valid] > 0).all()
        assert np.isfinite(f.xyz[f.valid]).all()
    assert frames[-1].meta.gps.has_position  # position packets reached position_port
    assert reader.counters["source"]["data_packets"] > 0


def test_stop_from_another_thread_ends_the_iteration(ports):
    data, position = ports
    reader = vlpground.live(data, "127.0.0.1", position_port=position)
    timer = threading.Timer(0.3, reader.stop)
    start = time.monotonic()
    timer.start()
    assert list(reader) == []  # no sender: nothing arrives, stop() ends it
    assert time.monotonic() - start < 5


def test_timeout_and_duration(ports):
    data, position = ports
    with pytest.raises(TimeoutError, match="no frame for"):
        list(vlpground.live(data, "127.0.0.1", position_port=position, timeout_s=0.3))
    start = time.monotonic()
    assert list(vlpground.live(data, "127.0.0.1", position_port=position, duration_s=0.3)) == []
    assert 0.25 < time.monotonic() - start < 5


def test_port_in_use_is_a_clear_error_and_close_frees_it(ports):
    data, position = ports
    with vlpground.live(data, "127.0.0.1", position_port=0) as first:
        with pytest.raises(RuntimeError, match="in use"):
            vlpground.live(data, "127.0.0.1", position_port=0)
    # Leaving the block released the socket although `first` is still referenced.
    second = vlpground.live(data, "127.0.0.1", position_port=0)
    second.close()
    assert list(first) == [] and first.counters["source"]["data_packets"] == 0


def test_ctrl_c_stops_a_waiting_live_loop(ports):
    """SIGINT (Ctrl-C in a terminal or a notebook's interrupt) raises KeyboardInterrupt."""
    data, position = ports
    script = textwrap.dedent(f"""
        import vlpground
        reader = vlpground.live({data}, "127.0.0.1", position_port={position})
        try:
            print("ready", flush=True)
            for frame in reader:
                pass
        except KeyboardInterrupt:
            print("interrupted", flush=True)
    """)
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        # The child is in (or about to enter) the packet wait, which holds no GIL: only the
        # reader's own signal checks between 0.1 s slices can end it.
        assert child.stdout.readline().strip() == "ready"
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=10)
    finally:
        child.kill()
    assert child.returncode == 0, err
    assert out.strip() == "interrupted"
