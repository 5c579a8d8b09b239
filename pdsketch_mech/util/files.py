"""Writing files so that a reader, or a crash, never sees half of one."""
from __future__ import annotations

import json
import os
import tempfile
from contextlib import contextmanager
from typing import IO, Any, Iterator


@contextmanager
def atomic_file(path: str, binary: bool = False, suffix: str = ".tmp") -> Iterator[IO]:
    """A temporary file beside `path`, opened for writing, that replaces `path` when the block
    ends without error (a reader, or a crash, never sees half a file; an existing file is
    only replaced by a complete one) and is removed otherwise. Permissions as open() gives."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=suffix)
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.fchmod(fd, 0o666 & ~umask)  # as open() would create it, not mkstemp's 0600
        with (os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", encoding="utf-8", newline="\n")) as handle:
            yield handle
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_text(path: str, text: str) -> None:
    """Write `text` to `path` atomically (`atomic_file`)."""
    with atomic_file(path) as handle:
        handle.write(text)


def write_json(path: str, document: Any) -> None:
    """Write `document` atomically (`atomic_file`)."""
    with atomic_file(path, suffix=".json") as handle:
        json.dump(document, handle, indent=1)
        handle.write("\n")
