"""What the console benchmarks share: the console in a tmux session, the
refresh rate it shows, and the lines of its traffic log (`:log`).
Standard library only."""

import os
import re
import subprocess
import time

SHOWN = re.compile(r"→ (\d+(?:\.\d+)?)/s")


class Tmux:
    """`command` in a tmux session of its own, 120x40."""

    def __init__(self, command, name):
        self.socket = f"axterm-bench-{name}-{os.getpid()}"
        subprocess.run(["tmux", "-L", self.socket, "-f", "/dev/null", "new-session", "-d",
                        "-x", "120", "-y", "40", command], check=True)

    def keys(self, *keys):
        subprocess.run(["tmux", "-L", self.socket, "send-keys", *keys], check=True)

    def screen(self):
        out = subprocess.run(["tmux", "-L", self.socket, "capture-pane", "-p", "-J"],
                             capture_output=True, text=True, check=False)
        return out.stdout

    def until(self, what, ready, timeout=30):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            screen = self.screen()
            if ready(screen):
                return screen
            time.sleep(0.1)
        raise SystemExit(f"gave up waiting for {what}:\n{self.screen()}")

    def close(self):
        subprocess.run(["tmux", "-L", self.socket, "kill-server"], check=False,
                       stderr=subprocess.DEVNULL)


def shown_rate(tmux):
    """The refresh rate the console shows (`poll 20 Hz → 8.7/s`), if any."""
    match = SHOWN.search(tmux.screen())
    return float(match.group(1)) if match else None


def unescape_len(text):
    """Bytes of a frame as an ASCII family's log shows it (`@01PP\\r`)."""
    count, i = 0, 0
    while i < len(text):
        if text[i] == "\\":
            i += 4 if text[i + 1:i + 2] == "x" else 2
        else:
            i += 1
        count += 1
    return count


def log_entry(line):
    """A `:log` line as (milliseconds since the log began, direction, who
    asked, frame), or None for a line that is not a frame:
    `2025-03-07T14:05:09.123Z     12.345 ms [L2 ]-> request     poll     @01PP\\r`
    (the link only when the console has several)."""
    parts = line.rstrip("\n").split(None, 3)
    if len(parts) < 4 or parts[2] != "ms":
        return None
    rest = parts[3]
    if rest[:1] == "L":
        rest = rest.split(None, 1)[1] if " " in rest else ""
    fields = rest.split(None, 3)
    if len(fields) < 4:
        return None
    direction, _kind, by, frame = fields
    return float(parts[1]), direction, by, frame
