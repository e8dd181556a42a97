#!/usr/bin/env bash
# Drives `filmsplat view` in a real headless browser (Debian's chromium package, through
# playwright-core). Installs what it needs when missing: chromium with apt-get (as root; else it
# says the command), playwright-core with npm into target/browser-test/. Then runs a script:
#   bash tests/browser/run.sh                                   # the end-to-end test
#   bash tests/browser/run.sh benches/view_browser.cjs [SCENE]  # frames/s in the browser
#   bash tests/browser/run.sh tests/browser/screenshots.cjs     # the README's screenshots
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ ! -x /usr/bin/chromium ]; then
    if [ "$(id -u)" = 0 ]; then
        echo "tests/browser: installing chromium (apt-get install -y chromium)" >&2
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
    else
        echo "tests/browser: needs /usr/bin/chromium: sudo apt-get install -y chromium" >&2
        exit 1
    fi
fi
modules=target/browser-test
if [ ! -f "$modules/node_modules/playwright-core/package.json" ]; then
    echo "tests/browser: installing playwright-core into $modules (npm)" >&2
    mkdir -p "$modules"
    npm install --silent --no-audit --no-fund --prefix "$modules" playwright-core@1 >/dev/null
fi
# Fresh after `cargo test --release` (same features, same profile): nothing is compiled again.
cargo build --release --locked --quiet
script="${1:-tests/browser/view.test.cjs}"
shift || true
FILMSPLAT_PLAYWRIGHT="$PWD/$modules/node_modules/playwright-core" \
    FILMSPLAT_BIN="$PWD/target/release/filmsplat" node "$script" "$@"
