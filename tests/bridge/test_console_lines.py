"""An agent node's console lines stay whole while rospy logs to the same stdout from other
threads (a log line once fell between an agent's text and its newline)."""

from __future__ import annotations

import io
import os
import threading

from rason.ros.node import write_line

LINES = 20_000


def _interleave(write_agent_line) -> list[str]:
    """Two threads on one text stream over a real pipe, unbuffered as the harness (and
    ``python -u``) makes stdout: agent lines written by ``write_agent_line``, log lines written
    whole as rospy's handler writes them."""
    read_end, write_end = os.pipe()
    stream = io.TextIOWrapper(io.FileIO(write_end, "w"), encoding="utf-8", write_through=True)
    chunks: list[bytes] = []

    def drain() -> None:
        while data := os.read(read_end, 1 << 16):
            chunks.append(data)

    def agent() -> None:
        for i in range(LINES):
            write_agent_line(stream, f"[boss] names [agent,boss,other] {i}")

    def logger() -> None:
        for i in range(LINES):
            stream.write(f"[INFO] [1795605516.{i:06d}]: agent other present\n")
            stream.flush()

    reader = threading.Thread(target=drain)
    reader.start()
    writers = [threading.Thread(target=agent), threading.Thread(target=logger)]
    for thread in writers:
        thread.start()
    for thread in writers:
        thread.join()
    stream.close()
    reader.join()
    os.close(read_end)
    return b"".join(chunks).decode().splitlines()


def test_agent_lines_and_log_lines_never_break_each_other() -> None:
    lines = _interleave(write_line)
    agent = [line for line in lines if line.startswith("[boss]")]
    log = [line for line in lines if line.startswith("[INFO]")]
    assert len(agent) == LINES and len(log) == LINES and len(lines) == 2 * LINES
    assert all(line.endswith("present") for line in log)
    assert [line.rsplit(" ", 1)[1] for line in agent] == [str(i) for i in range(LINES)]
