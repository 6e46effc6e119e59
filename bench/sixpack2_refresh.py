"""How often the console refreshes the status of a SIXpack 2's six motors,
against what the wire allows: the console (`axterm --port PTY --protocol
sixpack2 --baud N`) in tmux on a simulator served with the wire time of N
baud (`axterm sim sixpack2 --pty --baud N`), standing, with motor 1
rotating, and at `:poll 1000` (as fast as the line goes).

    cargo build --release
    python3 bench/sixpack2_refresh.py target/release/axterm [BAUD ...] [--seconds S]

A full refresh is twelve exchanges ($20 and $21 for each motor), each
9 bytes out and 8 back plus the unit's 6 ms switch-over delay before it
answers (§6.1.1); the slow $30 (reference inputs) takes at most a fortieth
of the line. For each baud rate and phase it prints the refresh rate the
console shows (`poll 20 Hz → 5.3/s`), the rate the wire allows for the
twelve exchanges alone (1 / (12 × (17 × 10 / baud + 6 ms))) and the share
of it reached. Needs tmux; standard library only.
"""

import subprocess
import sys
import tempfile
import time

from bench_support import Tmux, shown_rate

EXCHANGES = 12
BYTES = 17
SWITCH_OVER = 0.006


def shown_rates(tmux, seconds):
    """The rates the console shows, looked at every half second."""
    rates = []
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        rate = shown_rate(tmux)
        if rate is not None:
            rates.append(rate)
        time.sleep(0.5)
    return rates


def measure(binary, baud, seconds):
    sim = subprocess.Popen([binary, "sim", "sixpack2", "--pty", "--baud", str(baud)],
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    pty = sim.stdout.readline().strip()
    data = tempfile.mkdtemp()
    tmux = Tmux(f"AXTERM_DATA_DIR={data} {binary} --port {pty} --protocol sixpack2 --baud {baud}",
                f"sp2-{baud}")
    allowed = 1 / (EXCHANGES * (BYTES * 10 / baud + SWITCH_OVER))
    try:
        tmux.until("the console", lambda s: "→ " in s)
        phases = (("standing", None), ("m1 rotating", "ConstantRotation 1 300"),
                  ("rotating, :poll 1000", ":poll 1000"))
        for phase, line in phases:
            if line:
                tmux.keys("-l", line)
                tmux.keys("Enter")
            time.sleep(3)  # let the measured rate settle
            rates = shown_rates(tmux, seconds)
            if not rates:
                print(f"{baud:>6} {phase:<22} no rate shown")
                continue
            mean = sum(rates) / len(rates)
            print(f"{baud:>6} {phase:<22} shown {min(rates):4.1f}..{max(rates):4.1f}/s "
                  f"(mean {mean:4.2f})  wire allows {allowed:4.2f}/s  "
                  f"reached {100 * mean / allowed:5.1f} %")
        tmux.keys("F12")
        tmux.keys("F10")
    finally:
        tmux.close()
        sim.terminate()
        sim.wait()


def main():
    args = sys.argv[1:]
    seconds = 10.0
    if "--seconds" in args:
        at = args.index("--seconds")
        seconds = float(args[at + 1])
        del args[at:at + 2]
    binary = args[0]
    bauds = [int(b) for b in args[1:]] or [9600, 19200]
    for baud in bauds:
        measure(binary, baud, seconds)


main()
