#!/usr/bin/env bash
# Build the `lucent` Python wheel and run its tests (crates/lucent-py/tests).
#
# Needs only the Rust toolchain and python3 (3.9 or later): the first run
# makes a virtual environment in target/py-venv (in cargo's target directory,
# $CARGO_TARGET_DIR if set) and installs maturin, numpy,
# pytest, tqdm, dask[distributed] and pyoidn (Intel Open Image Denoise, for
# the denoising tests) into it, at the versions pinned in
# scripts/python-test-requirements.txt. The wheel is built in the
# workspace's target directory with the `testing` profile (so the lucent
# crate built by scripts/test.sh is reused), into target/wheels, and
# installed into that environment. Extra arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."

# Where cargo puts what it builds: target/, or $CARGO_TARGET_DIR (or a
# target-dir in a cargo config) when one is set.
target=$(cargo metadata --format-version 1 --no-deps --locked |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')
venv="$target/py-venv"
if [ ! -x "$venv/bin/python" ]; then
    echo "making $venv" >&2
    python3 -m venv "$venv"
fi
py="$venv/bin/python"
# Quiet, and only what is missing: a warm environment costs a second.
# The versions are pinned in scripts/python-test-requirements.txt.
if ! "$py" -c 'import maturin, numpy, pytest, tqdm, dask.distributed, cffi, importlib.util as u; assert u.find_spec("pyoidn")' 2>/dev/null; then
    "$py" -m pip install --quiet --disable-pip-version-check -r scripts/python-test-requirements.txt
fi

# The `testing` profile (Cargo.toml), as scripts/test.sh builds the crates:
# the lucent library built for `cargo test` is reused. The tests compare
# with the command-line program of the same build.
profile=testing
cargo build --profile "$profile" --locked --quiet -p lucent-cli
export LUCENT_CLI="$target/$profile/lucent"
rm -f "$target"/wheels/lucent-*.whl
"$venv/bin/maturin" build --profile "$profile" --locked --quiet -o "$target/wheels" --interpreter "$py"
"$py" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps "$target"/wheels/lucent-*.whl

# Tests run from outside the repository so that `import lucent` is the
# installed wheel, not the source tree.
exec "$py" -m pytest -q --rootdir="$PWD" "$PWD/crates/lucent-py/tests" "$@"
