"""Files derived once and kept between processes: the parser's tables, shapes' point clouds.

Every plan is a new process, so work that depends only on a file's content (the grammar's
LALR tables, an asset's point cloud) would otherwise be redone by each. The cache lives in
`$PDSKETCH_CACHE`, else `$XDG_CACHE_HOME/pdsketch_mech`, else `~/.cache/pdsketch_mech`.
Entries are named by a hash of everything they derive from, so a stale one is never read,
and written atomically, so concurrent processes never read half a file. A cache that cannot
be written (a read-only home) only costs the work again: nothing here raises OSError.
"""
from __future__ import annotations

import hashlib
import io
import os
import tempfile
import zlib
from typing import TYPE_CHECKING, Callable, Dict, Iterable, Optional, Union

if TYPE_CHECKING:  # numpy is imported where arrays are read or written: the parser needs none
    import numpy as np


def cache_dir() -> str:
    """The folder of the cache (not created here)."""
    return os.environ.get("PDSKETCH_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "pdsketch_mech")


def content_key(parts: Iterable[Union[str, bytes]]) -> str:
    """A short hash naming an entry by everything it derives from (texts and file contents)."""
    digest = hashlib.sha256()
    for part in parts:
        data = part.encode() if isinstance(part, str) else part
        digest.update(len(data).to_bytes(8, "little"))  # no two part lists hash alike by concatenation
        digest.update(data)
    return digest.hexdigest()[:24]


def entry_path(name: str) -> str:
    """Where the entry `name` (a file name, e.g. from `content_key`) is kept."""
    return os.path.join(cache_dir(), name)


def store(name: str, write: Callable[[object], None]) -> Optional[str]:
    """Write the entry `name` by calling `write` on a binary file handle, atomically; the
    entry's path, or None when the cache cannot be written."""
    path = entry_path(name)
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), prefix=".tmp-")
    except OSError:
        return None
    try:
        with os.fdopen(fd, "wb") as handle:
            write(handle)
        os.replace(tmp, path)
        return path
    except OSError:
        return None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def load_arrays(name: str) -> Optional[Dict[str, "np.ndarray"]]:
    """The arrays of the entry `name` (an .npz written by `store_arrays`), or None when it is
    missing or damaged. Never unpickles: an entry is data only."""
    import numpy as np
    try:
        with np.load(entry_path(name), allow_pickle=False) as entry:
            return {key: entry[key] for key in entry.files}
    except (OSError, ValueError, KeyError, EOFError, zlib.error):
        return None


def store_arrays(name: str, **arrays: "np.ndarray") -> Optional[str]:
    """Write `arrays` as the entry `name` (.npz, atomically); its path, or None (`store`)."""
    import numpy as np
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return store(name, lambda handle: handle.write(buffer.getvalue()))

