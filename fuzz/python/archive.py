"""Coverage-guided fuzzing of the Dask scene-archive unpacker
(``lucent._archive``: ``unpack``, then ``load_arguments``) with atheris,
libFuzzer for Python.

    fuzz/python/run.sh SECONDS

Every input is unpacked into a fresh cache directory. It must be refused
with ``ArchiveError`` or unpack into that directory, giving a scene path
(and an environment map) inside it; any other exception is a finding.
The module is loaded from its file, so the native extension is not
needed. Seeds: ``fuzz/seeds/archive`` (``fuzz/python/make-archive-seeds.py``);
findings go to ``fuzz/regressions/archive``, which
``crates/lucent-py/tests/test_archive_inputs.py`` replays.
"""

import hashlib
import importlib.util
import os
import shutil
import sys
import tempfile

import atheris

HERE = os.path.dirname(os.path.abspath(__file__))
MODULE = os.path.join(HERE, "..", "..", "crates", "lucent-py", "python", "lucent", "_archive.py")

spec = importlib.util.spec_from_file_location("lucent_archive", MODULE)
archive = importlib.util.module_from_spec(spec)
sys.modules["lucent_archive"] = archive
spec.loader.exec_module(archive)


def inside(path, root):
    return os.path.commonpath([os.path.realpath(path), os.path.realpath(root)]) == os.path.realpath(root)


def test_one_input(data: bytes):
    cache = tempfile.mkdtemp(prefix="lucent-archive-fuzz-")
    try:
        sha = hashlib.sha256(data).hexdigest()
        try:
            files, manifest = archive.unpack(data, sha, cache)
        except archive.ArchiveError:
            return
        scene, options = archive.load_arguments(files, manifest)
        assert inside(scene, files), (scene, files)
        if "env" in options:
            assert inside(options["env"], files), (options["env"], files)
        # Nothing is left beside the unpacked directory.
        assert os.listdir(cache) == [sha], os.listdir(cache)
    finally:
        shutil.rmtree(cache, ignore_errors=True)


if __name__ == "__main__":
    atheris.instrument_all()
    atheris.Setup(sys.argv, test_one_input)
    atheris.Fuzz()
