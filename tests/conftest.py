import os

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "tests", "data")


@pytest.fixture(autouse=True, scope="session")
def own_disk_cache(tmp_path_factory):
    """The suite (and the commands it runs) keeps derived files (disk_cache.py) in a folder of
    its own: it neither reads what the user's plans left nor leaves anything there."""
    previous = os.environ.get("PDSKETCH_CACHE")
    os.environ["PDSKETCH_CACHE"] = str(tmp_path_factory.mktemp("cache"))
    yield
    if previous is None:
        del os.environ["PDSKETCH_CACHE"]
    else:
        os.environ["PDSKETCH_CACHE"] = previous


@pytest.fixture
def write_files(tmp_path):
    """Write {relative name: text} under a temporary folder; returns the paths, in order."""
    def write(**files):
        paths = []
        for name, text in files.items():
            path = tmp_path / name.replace("__", "/")
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
            paths.append(str(path))
        return paths
    return write
