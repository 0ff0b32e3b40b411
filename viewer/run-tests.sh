#!/usr/bin/env bash
# The viewer's tests: installs what they need, builds the page and runs
#   1. node --test: the page's weight-stream reader and ARKit name parser;
#   2. tests/e2e.mjs: the page in headless Chromium against `likeness view`
#      (builds the likeness command with cargo; honours CARGO_TARGET_DIR).
# Installs: the npm packages pinned in package-lock.json (npm ci, from the
# npm registry), and Debian's chromium with apt-get when it is missing and
# we are root. CHROMIUM=/path/to/chromium uses another Chromium.
# About 30 s once the Rust build and node_modules are in place.
set -euo pipefail
cd "$(dirname "$0")"

if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    echo "viewer/run-tests.sh: Node.js 18 or later with npm is needed" >&2
    exit 1
fi
npm ci --no-audit --no-fund --loglevel=error
npm run --silent build

chromium=${CHROMIUM:-/usr/bin/chromium}
if [ ! -x "$chromium" ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "viewer/run-tests.sh: installing Debian's chromium" >&2
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
    else
        echo "viewer/run-tests.sh: no Chromium at $chromium: apt-get install chromium, or set CHROMIUM" >&2
        exit 1
    fi
fi
export CHROMIUM=$chromium

node --test --test-reporter=spec tests/weight-stream.test.mjs
node tests/e2e.mjs
