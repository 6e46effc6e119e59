"""What the console costs: time to the first frame, then CPU and bytes
written to the terminal per second while one axis is polled at 20 Hz,
standing still and moving. Runs the console in a pseudo-terminal of
100x30 and reads everything it writes. Standard library only.

    cargo build --release
    python3 bench/console_cost.py target/release/axterm [SECONDS] [served] [KIND]
    python3 bench/console_cost.py target/release/axterm [SECONDS] \
        --sim tmcm1110 --address 1-4 --sim tmcm1110 --address 1-4

By default the console runs `--sim tmcm1110`, the simulator inside the
console's process (its 1 ms clock counts against the console's CPU).
With `served`, the simulator runs in a process of its own (`axterm sim
KIND --pty`) and the console talks to it as to a serial port, which
is what the console costs on a real line. KIND is one of MOVES' keys
(tmcm1110 unless given); its first axis is moved.

Given connection options instead of KIND (TMCM-1110 modules only), the
console runs on them, and "moving" means every module the options name
turns (`:module N` then `ROR 0, 300`, for each module of the list).

With CONSOLE_COST_DUMP=FILE in the environment, the bytes written while
moving are kept in FILE, to see which cells change.
"""

import fcntl
import os
import pty
import select
import subprocess
import struct
import sys
import tempfile
import termios
import time

F10 = b"\x1b[21~"
# Per simulator kind: the line that moves its first axis at a constant
# speed, the line that stops it, and the console's --protocol for it.
MOVES = {
    "tmcm1110": ("ROR 0, 300", "MST 0", "tmcl"),
    "cmd4cr": ("JX+", "STOPX", "cmd4cr"),
}
CLOCK_TICK = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as stat:
        fields = stat.read().rsplit(")", 1)[1].split()
    # utime and stime are fields 14 and 15 of the whole line; after the
    # command name's ")" they are the 12th and 13th.
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICK


def module_count(connection):
    """Modules the options name: one a link, or each of an --address
    list (1-4, 1,3,7)."""
    count, link, addresses = 0, False, 1
    for flag, value in zip(connection, connection[1:] + [""]):
        if flag in ("--sim", "--port", "--tcp"):
            count += addresses if link else 0
            link, addresses = True, 1
        elif flag == "--address":
            addresses = 0
            for part in value.split(","):
                low, _, high = part.partition("-")
                addresses += int(high or low) - int(low) + 1
    return count + (addresses if link else 0)


def main():
    binary = sys.argv[1]
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
    options = sys.argv[3:]
    given = bool(options) and options[0].startswith("--")
    served = not given and "served" in options
    kinds = [a for a in options if a != "served"]
    kind = kinds[0] if kinds and not given else "tmcm1110"
    move, stop, protocol = MOVES[kind]
    dump = os.environ.get("CONSOLE_COST_DUMP")
    connection = options if given else ["--sim", kind]
    modules = module_count(connection)
    if served:
        sim = subprocess.Popen([binary, "sim", kind, "--pty"],
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        connection = ["--port", sim.stdout.readline().strip(), "--protocol", protocol]
    data = tempfile.mkdtemp()
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 30, 100, 0, 0))
    started = time.monotonic()
    pid = os.fork()
    if pid == 0:
        os.setsid()
        fcntl.ioctl(slave, termios.TIOCSCTTY, 0)
        for fd in (0, 1, 2):
            os.dup2(slave, fd)
        os.environ["AXTERM_DATA_DIR"] = data
        os.environ["TERM"] = "xterm-256color"
        os.execv(binary, [binary] + connection)
    os.close(slave)
    seen = bytearray()
    total = 0

    def pump(until):
        nonlocal total
        while True:
            left = until - time.monotonic()
            if left <= 0:
                return
            ready, _, _ = select.select([master], [], [], left)
            if ready:
                try:
                    chunk = os.read(master, 65536)
                except OSError:
                    return
                total += len(chunk)
                if len(seen) < 4_000_000:
                    seen.extend(chunk)

    first_frame = None
    deadline = started + 10
    while first_frame is None and time.monotonic() < deadline:
        pump(time.monotonic() + 0.001)
        if b"F12 STOP" in seen:
            first_frame = time.monotonic() - started
    first_bytes = total
    # Let the first values come in and settle.
    pump(time.monotonic() + 3)

    def window(label):
        bytes_before, cpu_before, t0 = total, cpu_seconds(pid), time.monotonic()
        seen_before = len(seen)
        pump(t0 + seconds)
        if dump and label == "moving":
            with open(dump, "wb") as out:
                out.write(seen[seen_before:])
        elapsed = time.monotonic() - t0
        cpu = cpu_seconds(pid) - cpu_before
        print(f"{label:<12} {(total - bytes_before) / elapsed:9.0f} B/s   "
              f"{100 * cpu / elapsed:6.2f} % of a core   ({elapsed:.1f} s)")

    print(f"first frame  {1000 * first_frame:9.1f} ms   ({first_bytes} bytes)"
          if first_frame else "first frame  never seen")
    window("standing")
    for module in range(1, modules + 1):
        if modules > 1:
            os.write(master, f":module {module}\r".encode())
        os.write(master, move.encode() + b"\r")
        pump(time.monotonic() + 0.2)
    pump(time.monotonic() + 1)
    window("moving")
    os.write(master, (":stop" if modules > 1 else stop).encode() + b"\r")
    pump(time.monotonic() + 1)
    os.write(master, F10)
    pump(time.monotonic() + 2)
    os.waitpid(pid, 0)
    if served:
        sim.terminate()
        sim.wait()


main()
