"""saggriac.files: the one lock of the package (a run's target, a study folder)."""

import pytest

from saggriac import files
from saggriac.errors import StorageError


def test_a_held_lock_refuses_a_second_holder_with_the_callers_message(tmp_path):
    path = tmp_path / ".x.lock"
    with files.lock(path, "busy: wait") as unlocked:
        assert unlocked is None and path.exists()
        with pytest.raises(StorageError, match="^busy: wait$"):
            with files.lock(path, "busy: wait"):
                pass
    with files.lock(path, "busy"):  # released: free again
        pass
    assert path.exists()


def test_the_lock_file_is_removed_on_release_when_asked(tmp_path):
    path = tmp_path / ".x.lock"
    with pytest.raises(RuntimeError):
        with files.lock(path, "busy", remove=True):
            raise RuntimeError("the block failed")
    assert not path.exists()
