#!/usr/bin/env bash
# Installs the official BIDS validator (the npm package bids-validator, 1.x)
# into PREFIX for the test runner.bids_validator (validate.sh). Once: a
# validator installed there by an earlier run is kept.
#   install.sh PREFIX
# `make test` starts it in the background before building, so the download
# overlaps the compilation; the ctest fixture's run then waits for that one
# (a lock beside PREFIX) and finds the validator installed.
set -euo pipefail
prefix=$1
validator=$prefix/node_modules/.bin/bids-validator
mkdir -p "$(dirname "$prefix")"
exec 9> "$prefix.lock"
flock 9
if [[ -x $validator ]] && version=$("$validator" --version 2>/dev/null); then
  echo "bids-validator $version is installed in $prefix"
  exit 0
fi
for command in node npm; do
  if ! command -v "$command" > /dev/null; then
    echo "$command not found: the BIDS validator needs Node.js and npm" \
         "('make deps' installs them on Debian)" >&2
    exit 1
  fi
done
mkdir -p "$prefix"
npm install --prefix "$prefix" bids-validator@1 --no-audit --no-fund
echo "bids-validator $("$validator" --version) installed in $prefix"
