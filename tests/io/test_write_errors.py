"""A full disk while writing an output is reported in one line naming the file: a sweep's journal (as the sweep starts
and between its points) and a command's lock file; a buffered line failing again on the way out does not replace
that report with a bare "No space left on device"."""

import builtins
import errno
import io

import pytest

from elastoactive.cli import main
from elastoactive.io import outputs
from elastoactive.sweep import store

SWEEP = ["sweep", "one-pinned", "--n", "3", "--engine", "reduced", "--preset", "fast", "--duration", "5"]


class FullDisk(io.TextIOWrapper):
    """A text file on a disk that fills after `room` flushes: the lines written since stay in the buffer, and every
    later flush (close's included) fails with ENOSPC, as a buffered file's does."""

    def __init__(self, path, mode, room, **kwargs):
        super().__init__(builtins.open(path, mode.replace("+", "") + "b+" if "+" in mode else mode + "b"), **kwargs)
        self.room, self.pending = room, False

    def write(self, text):
        self.pending = True
        return super().write(text)

    def flush(self):
        if self.pending and self.room <= 0:
            raise OSError(errno.ENOSPC, "No space left on device")
        if self.pending:
            self.room -= 1
        self.pending = False
        super().flush()

    def close(self):
        try:
            self.flush()
        finally:
            self.buffer.close()


def full_after(monkeypatch, module, room, suffix):
    """Files opened by `module` whose name ends in `suffix` fill the disk after `room` flushes."""

    def opened(path, mode="r", *args, **kwargs):
        if str(path).endswith(suffix):
            return FullDisk(path, mode, room, encoding=kwargs.get("encoding"), errors=kwargs.get("errors"))
        return builtins.open(path, mode, *args, **kwargs)

    monkeypatch.setattr(module, "open", opened, raising=False)


@pytest.mark.parametrize("room, when", [(0, "as the sweep starts"), (1, "after its header")])
def test_a_full_disk_on_the_journal_names_it(tmp_path, monkeypatch, capsys, room, when):
    out = tmp_path / "s.nc"
    full_after(monkeypatch, store, room, ".journal")
    code = main([*SWEEP, "--grid", "sigma=0.3,0.6", "--out", str(out), "--workers", "1", "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, (when, err)
    assert f"cannot append to the journal {out}.journal: no space left on the device" in err[0], (when, err)


def test_a_full_disk_on_a_lock_file_names_it(tmp_path, monkeypatch):
    lock = tmp_path / "out.nc.lock"
    full_after(monkeypatch, outputs, 0, ".lock")
    with pytest.raises(OSError) as failed, outputs.lock_file(lock, "ramp"):
        pass
    assert failed.value.filename == str(lock) and failed.value.errno == errno.ENOSPC
    assert "No space left on device" in failed.value.strerror and not lock.exists()
