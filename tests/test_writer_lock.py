"""One writer per output: the lock refuses a second holder at once and dies with its holder."""

import subprocess
import sys

import pytest

from mobilemani_rl.utils.errors import InputError
from mobilemani_rl.utils.writer_lock import WriterLock

HOLD = "import sys, time; from pathlib import Path; from mobilemani_rl.utils.writer_lock import WriterLock; "
HOLD += "lock = WriterLock(Path(sys.argv[1]), 'busy'); print('held', flush=True); time.sleep(120)"


def test_a_second_writer_is_refused_until_the_first_releases(tmp_path):
    path = tmp_path / "run" / "train.lock"
    with WriterLock(path, "first"):
        with pytest.raises(InputError, match="^another run holds it$"):
            WriterLock(path, "another run holds it")
    with WriterLock(path, "second"):  # released by the block's end
        pass


def test_a_killed_holder_leaves_no_stale_lock(tmp_path):
    path = tmp_path / "train.lock"
    holder = subprocess.Popen([sys.executable, "-c", HOLD, str(path)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(InputError, match="busy"):
            WriterLock(path, "busy")
    finally:
        holder.kill()  # SIGKILL: no cleanup runs in the holder
        holder.wait()
    WriterLock(path, "busy").release()
