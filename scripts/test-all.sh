#!/usr/bin/env bash
# The project's test command: the Rust tests, then the Python package's.
#
#   scripts/test-all.sh            # Rust tests, then build + pytest in .venv-test
#   VENV=/path/to/venv scripts/test-all.sh   # reuse (or create) that venv
#   SKIP_RUST=1 scripts/test-all.sh          # only the Python part
#
# The Python part creates the virtual environment if it does not exist,
# installs maturin, numpy and pytest from PyPI (and, for the comparison
# tests, triangle, tetgen, meshio, scipy, tqdm and matplotlib; a package that cannot be
# installed only skips its comparison tests, visibly in pytest's summary),
# builds the package into the workspace's target directory (so the build
# reuses the Rust compilation) and runs pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$ROOT/target}

if [ -z "${SKIP_RUST:-}" ]; then
    # The fuzz targets' short run: 2 s per target (see fuzz/README.md).
    DELONE_FUZZ_SECS=${DELONE_FUZZ_SECS:-2} cargo test --workspace
fi

PYTHON=${PYTHON:-python3}
VENV=${VENV:-$ROOT/.venv-test}
if [ ! -x "$VENV/bin/python" ]; then
    "$PYTHON" -m venv "$VENV"
fi
PY=$VENV/bin/python
"$PY" -m pip install --quiet --upgrade pip
"$PY" -m pip install --quiet "maturin>=1.5,<2" numpy pytest
for optional in triangle tetgen meshio scipy tqdm matplotlib; do
    "$PY" -m pip install --quiet "$optional" || echo "note: $optional not installed; its comparison tests are skipped"
done
# Build the wheel with the workspace's release profile and install it (the
# same as `pip install .`, without copying the target directory).
rm -rf "$CARGO_TARGET_DIR/wheels"
"$VENV/bin/maturin" build --release --quiet --interpreter "$PY" --out "$CARGO_TARGET_DIR/wheels"
"$PY" -m pip install --quiet --force-reinstall --no-deps "$CARGO_TARGET_DIR"/wheels/delone-*.whl
# Run from the tests folder so that `import delone` is the installed package.
cd python/tests
MPLBACKEND=Agg "$PY" -m pytest -q -p no:cacheprovider .
