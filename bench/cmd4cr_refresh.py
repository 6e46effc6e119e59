"""How often the console refreshes the status of a CMD-4CR's four axes,
against what the wire allows: the console (`axterm --port PTY --protocol
cmd4cr --baud N`) in tmux on a simulator served with the wire time of N
baud (`axterm sim cmd4cr --pty --baud N`), standing and with X jogging.

    cargo build --release
    python3 bench/cmd4cr_refresh.py target/release/axterm [BAUD ...] [--seconds S]

For each baud rate and phase it prints the refresh rate the console shows
(`poll 20 Hz → 8.7/s`) at the default 20 Hz and at `:poll 1000` (as
fast as the line goes), the rounds of the fast poll items counted in the
console's traffic log (`:log`), the bytes one round and its share of the
slow items put on the wire, the rate the wire would allow for the fast
items alone (baud / 10 bits / bytes per round), the fraction of it
reached, and how busy the line was. Needs tmux; standard library only.
"""

import os
import re
import subprocess
import sys
import tempfile
import time

from bench_support import Tmux, shown_rate, unescape_len, log_entry

FAST = re.compile(r"^(PP|MST[XYZU]|PS[XYZU])$")


def window(log_path, start_ms, end_ms):
    """Poll traffic of the log between two times: rounds, bytes."""
    rounds, fast_bytes, slow_bytes = 0, 0, 0
    current = None
    with open(log_path) as log:
        for line in log:
            entry = log_entry(line)
            if entry is None:
                continue
            at, direction, by, frame = entry
            if not start_ms <= at < end_ms or by not in ("poll", "-"):
                continue
            if direction == "->":
                if by != "poll":
                    current = None
                    continue
                current = frame[3:].removesuffix("\\r")
                if current == "PP":
                    rounds += 1
            if current is None:
                continue
            # An answer is logged as the framer cut it, without its CR.
            size = unescape_len(frame) + (1 if direction == "<-" else 0)
            if FAST.match(current):
                fast_bytes += size
            else:
                slow_bytes += size
    return rounds, fast_bytes, slow_bytes


def measure(binary, baud, seconds):
    sim = subprocess.Popen([binary, "sim", "cmd4cr", "--pty", "--baud", str(baud)],
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    pty = sim.stdout.readline().strip()
    data = tempfile.mkdtemp()
    log_path = os.path.join(data, "traffic.log")
    tmux = Tmux(f"AXTERM_DATA_DIR={data} {binary} --port {pty} --protocol cmd4cr --baud {baud}",
                str(baud))
    try:
        tmux.until("the console", lambda s: "→ " in s)
        tmux.keys("-l", f":log {log_path}")
        tmux.keys("Enter")
        tmux.until("the log", lambda s: "logging every frame" in s)
        log_started = time.monotonic()
        results = []
        phases = (("standing", None), ("X jogging", "JX+"), ("jog, :poll 1000", ":poll 1000"))
        for phase, line in phases:
            if line:
                tmux.keys("-l", line)
                tmux.keys("Enter")
            time.sleep(2)  # let the measured rate settle on the new replies
            t0 = time.monotonic()
            time.sleep(seconds)
            t1 = time.monotonic()
            shown = shown_rate(tmux)
            results.append((phase, shown, (t0 - log_started) * 1000, (t1 - log_started) * 1000,
                            t1 - t0))
        tmux.keys("F12")
        tmux.keys("-l", ":log off")
        tmux.keys("Enter")
        tmux.until("the log closed", lambda s: "closed:" in s)
        tmux.keys("F10")
    finally:
        tmux.close()
        sim.terminate()
        sim.wait()
    # The log's clock starts at its first frame, at most a screen look
    # (0.1 s) before the console said it logs: the windows are that close.
    for phase, shown, start_ms, end_ms, elapsed in results:
        rounds, fast, slow = window(log_path, start_ms, end_ms)
        if rounds == 0:
            print(f"{baud:>6} {phase:<15} no rounds logged")
            continue
        per_round = fast / rounds
        allowed = baud / 10 / per_round
        counted = rounds / elapsed
        busy = (fast + slow) * 10 / baud / elapsed
        print(f"{baud:>6} {phase:<15} shown {shown if shown is not None else '-':>5}/s  "
              f"counted {counted:5.2f}/s  round {per_round:5.1f} B (+{slow / rounds:4.1f} B slow)  "
              f"wire allows {allowed:6.2f}/s  reached {100 * counted / allowed:5.1f} %  "
              f"line busy {100 * busy:5.1f} %")


def main():
    args = sys.argv[1:]
    seconds = 10.0
    if "--seconds" in args:
        at = args.index("--seconds")
        seconds = float(args[at + 1])
        del args[at:at + 2]
    binary = args[0]
    bauds = [int(b) for b in args[1:]] or [9600, 115200]
    for baud in bauds:
        measure(binary, baud, seconds)


main()
