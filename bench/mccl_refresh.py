"""How often the console refreshes the status of a MultiFlex's five axes
(four servos, a stepper), against what the wire allows: the console
(`axterm --port PTY --protocol mccl --baud N`) in tmux on a simulator
served with the wire time of N baud (`axterm sim mccl --pty --baud N`),
standing and with axis 1 turning in velocity mode.

    cargo build --release
    python3 bench/mccl_refresh.py target/release/axterm [BAUD ...] [--seconds S]

For each baud rate and phase it prints the refresh rate the console shows
(`poll 20 Hz → 7.3/s`) at the default 20 Hz and at `:poll 1000` (as fast
as the line goes), the rounds of the fast poll items (`aTP,TV,TS` for the
five axes, on one line or several: a round starts with the line that
reads axis 1) counted in the console's traffic log (`:log`), the bytes of
one round on the wire (the requests, their echo, three reply lines an axis
and the prompts; the log shows lines without their CR LF, which are added
back) and the slow items' share (`aTT,TF`, `5TT`), the rate the wire would allow for the
fast items alone, the fraction of it reached, and how busy the line was.
The line is full duplex and the controller echoes each character as it
arrives, so a request travels under its own echo: the answer direction is
the busier one and sets the limit (baud / 10 bits / answer bytes per
round), and how busy the line was is that direction's share. Needs tmux;
standard library only.
"""

import os
import re
import subprocess
import sys
import tempfile
import time

from bench_support import Tmux, shown_rate, unescape_len, log_entry

FAST = re.compile(r"^[1-8]TP,TV,TS(,[1-8]TP,TV,TS)*$")


def window(log_path, start_ms, end_ms):
    """Poll traffic of the log between two times: rounds, bytes."""
    rounds, fast_bytes, slow_bytes, fast_in, slow_in = 0, 0, 0, 0, 0
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
                current = frame.removesuffix("\\r")
                if current.startswith("1TP,TV,TS") and FAST.match(current):
                    rounds += 1
            if current is None:
                continue
            # A line is logged as the framer cut it, without its CR LF;
            # the prompt ends no line.
            size = unescape_len(frame)
            if direction == "<-" and frame != ">":
                size += 2
            if FAST.match(current):
                fast_bytes += size
                fast_in += size if direction == "<-" else 0
            else:
                slow_bytes += size
                slow_in += size if direction == "<-" else 0
    return rounds, fast_bytes, slow_bytes, fast_in, slow_in


def measure(binary, baud, seconds):
    sim = subprocess.Popen([binary, "sim", "mccl", "--pty", "--baud", str(baud)],
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    pty = sim.stdout.readline().strip()
    data = tempfile.mkdtemp()
    log_path = os.path.join(data, "traffic.log")
    tmux = Tmux(f"AXTERM_DATA_DIR={data} {binary} --port {pty} --protocol mccl --baud {baud}",
                str(baud))
    try:
        tmux.until("the console", lambda s: "→ " in s, timeout=60)
        tmux.keys("-l", f":log {log_path}")
        tmux.keys("Enter")
        tmux.until("the log", lambda s: "logging every frame" in s, timeout=60)
        log_started = time.monotonic()
        results = []
        phases = (("standing", None), ("axis 1 turning", "1MN,1VM,1SV20000,1GO"),
                  ("turning, :poll 1000", ":poll 1000"))
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
        tmux.until("the log closed", lambda s: "closed:" in s, timeout=60)
        tmux.keys("F10")
    finally:
        tmux.close()
        sim.terminate()
        sim.wait()
    for phase, shown, start_ms, end_ms, elapsed in results:
        rounds, fast, slow, fast_in, slow_in = window(log_path, start_ms, end_ms)
        if rounds == 0:
            print(f"{baud:>6} {phase:<20} no rounds logged")
            continue
        per_round = fast_in / rounds
        allowed = baud / 10 / per_round
        counted = rounds / elapsed
        busy = (fast_in + slow_in) * 10 / baud / elapsed
        print(f"{baud:>6} {phase:<20} shown {shown if shown is not None else '-':>5}/s  "
              f"counted {counted:5.2f}/s  round {fast / rounds:5.1f} B, {per_round:5.1f} B back "
              f"(+{slow_in / rounds:4.1f} B slow)  wire allows {allowed:6.2f}/s  "
              f"reached {100 * counted / allowed:5.1f} %  answer line busy {100 * busy:5.1f} %")


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
