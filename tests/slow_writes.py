"""``python -c RUNNER ARGS``: plbar's command line whose write of the file named ``$PLBAR_TEST_SLOW`` crawls (64
characters every 20 ms), so that a kill or a Ctrl-C lands inside it (importable: the tests' folder is on sys.path,
as for tests/shared_points.py).  SIGINT is Python's KeyboardInterrupt in it, whatever the parent ignored."""

RUNNER = r"""
import os, signal, sys, time
signal.signal(signal.SIGINT, signal.default_int_handler)
import plbar.util.files as files
slow = os.environ.get("PLBAR_TEST_SLOW")
if slow:
    _write = files.write_text
    def write_text(path, text):
        if os.path.basename(str(path)) != slow:
            return _write(path, text)
        with files.atomic_path(path) as tmp:
            with open(tmp, "w") as fh:
                for i in range(0, len(text), 64):
                    fh.write(text[i:i + 64]); fh.flush(); time.sleep(0.02)
        return path
    files.write_text = write_text
import plbar.cli
sys.exit(plbar.cli.main(sys.argv[1:]))
"""
