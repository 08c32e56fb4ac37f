#!/usr/bin/env bash
# The whole test suite, as README.md gives it and .ci/run runs it: the Rust
# crates (library, command line), then the Python package built as a wheel
# into a fresh virtual environment (scripts/test-python.sh). Needs the Rust
# toolchain and python3 (3.9 or later); everything else is fetched by cargo
# and pip, at the versions pinned in Cargo.lock and
# scripts/python-test-requirements.txt. Both build with the `testing`
# profile of Cargo.toml: release optimisation, without the link-time
# optimisation across crates that only makes the 33 test programs slow to
# link.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace --profile testing --locked
bash scripts/test-python.sh
