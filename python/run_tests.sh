#!/usr/bin/env bash
# The Python package's tests: builds the extension once (release) into its own virtual
# environment (target/python-venv, or $FILMSPLAT_VENV), installs it the way users do
# (`pip install ./python`) and runs pytest on python/tests. Any failure fails the script,
# and so does pytest collecting no tests (its exit code 5).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
venv="${FILMSPLAT_VENV:-$root/target/python-venv}"
python="${PYTHON:-python3}"
start=$(date +%s)
if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv"
fi
export PATH="$venv/bin:$PATH"
pip=("$venv/bin/python" -m pip --disable-pip-version-check)
"${pip[@]}" install -q 'maturin>=1.5,<2' 'numpy>=1.21' 'pytest>=7'
# One release build, in the workspace's target folder: this crate and the dependencies that
# cargo test built with the same features are reused.
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
export CARGO_BUILD_JOBS="${CARGO_BUILD_JOBS:-2}"
# The workspace's lock file (Cargo.lock, which python/ shares) must be current: a stale one
# would be rewritten by the build (a tracked file changed by `pip install ./python`). Checked
# here, and the build is --locked.
cargo metadata --locked --format-version 1 --manifest-path "$root/python/Cargo.toml" >/dev/null
export MATURIN_PEP517_ARGS="${MATURIN_PEP517_ARGS:---locked}"
"${pip[@]}" install -q --no-build-isolation --no-deps --force-reinstall "$root/python"
built=$(date +%s)
echo "python: venv and build took $((built - start)) s"
cd "$root/python/tests"
status=0
# Not `python -m pytest`: that would put python/ (the uncompiled source) on sys.path.
"$venv/bin/pytest" -q . || status=$?
if [ "$status" -eq 5 ]; then
    echo "python: pytest collected no tests" >&2
fi
# Nothing printed after pytest: its summary line ("N passed in T s") is the run's last line.
exit "$status"
