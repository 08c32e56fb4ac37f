"""Ctrl-C during a render raises KeyboardInterrupt and the process ends
cleanly."""

import signal
import subprocess
import sys
import time

from conftest import SCENES

CHILD = """
import signal, sys, time, lucent
# A process started in the background by a non-interactive shell (a CI
# job run as `cmd &`) inherits SIGINT ignored, and Python then leaves it
# ignored: give the child Python's own handler, as an interactive one has.
signal.signal(signal.SIGINT, signal.default_int_handler)
scene = lucent.load(sys.argv[1])
print("rendering", flush=True)
started = time.monotonic()
try:
    scene.render(width=512, height=512, spp=4096, threads=1, progress=False)
except KeyboardInterrupt:
    print(f"interrupted after {time.monotonic() - started:.1f} s", flush=True)
    # The interpreter still works, and so does the library.
    image = scene.render(width=8, height=8, spp=1, progress=False)
    print("then rendered", image.shape, flush=True)
    sys.exit(3)
print("finished: the render was not interrupted", flush=True)
"""


def test_ctrl_c_raises_keyboard_interrupt():
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, str(SCENES / "cornell-box.toml")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout.readline() == "rendering\n"
        time.sleep(0.5)  # inside the render (minutes long)
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=30)
    finally:
        if child.poll() is None:
            child.kill()
    assert child.returncode == 3, (out, err)
    lines = out.splitlines()
    assert lines[0].startswith("interrupted after "), out
    assert float(lines[0].split()[2]) < 10
    assert lines[1] == "then rendered (8, 8, 3)"
    assert err == ""
