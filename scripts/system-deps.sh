#!/usr/bin/env bash
# Debian packages the tests and benchmarks use: headless Chromium (browser tests),
# poppler-utils (pdftoppm: the PDF report to PNG), wrk (the ingest benchmark's load), curl
# (the README's walkthrough, run as printed) and postgresql (the cluster deployment's tests
# start a throwaway server of their own).
# Installs what is missing when run as root with apt; otherwise says what to install.
set -euo pipefail
need=()
command -v chromium >/dev/null 2>&1 || need+=(chromium)
command -v pdftoppm >/dev/null 2>&1 || need+=(poppler-utils)
command -v wrk >/dev/null 2>&1 || need+=(wrk)
command -v curl >/dev/null 2>&1 || need+=(curl)
compgen -G '/usr/lib/postgresql/*/bin/pg_ctl' >/dev/null || need+=(postgresql)
[ ${#need[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; then
  echo "installing Debian packages: ${need[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq >/dev/null
  apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
else
  echo "missing Debian packages: ${need[*]} (sudo apt-get install ${need[*]});" \
       "the tests that need them are skipped" >&2
fi
