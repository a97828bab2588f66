#!/usr/bin/env bash
# Runs s1_llvmpipe.py (Mesa's llvmpipe drawing the standard scene S1) with the given arguments,
# after making sure that what it needs is installed:
#   - Mesa's EGL and OpenGL with llvmpipe (Debian packages, apt-get; only the missing ones);
#   - a Python virtual environment with pinned moderngl, glcontext and numpy (only if one of
#     them is missing or at another version).
# Every step is skipped when already done, so the script can sit in a loop. See README.md.
#
#   benches/llvmpipe/run.sh --mesh assets/meshes/bunny.obj --modes phong --size 1280x720 --threads 2
#   benches/llvmpipe/run.sh --setup-only
#
# Environment: PHOSPHOR_LLVMPIPE_VENV (default: target/llvmpipe/venv in the repository),
# PYTHON (the interpreter that creates the venv, default python3).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
venv=${PHOSPHOR_LLVMPIPE_VENV:-$repo/target/llvmpipe/venv}
python=${PYTHON:-python3}

debian_packages=(libegl1 libgl1 libegl-mesa0 libgl1-mesa-dri)
python_packages=(moderngl==5.13.0 glcontext==3.1.0 numpy==2.2.6)

say() { echo "run.sh: $*" >&2; }

as_root() {
  if [ "$(id -u)" -eq 0 ]; then
    "$@"
  elif command -v sudo >/dev/null; then
    sudo "$@"
  else
    say "error: need root (or sudo) to run: $*"
    exit 1
  fi
}

installed() {
  [ "$(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null)" = installed ]
}

apt_install() {
  # A stale package list makes apt-get install fail to find files: refresh once and retry.
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >&2 ||
    { as_root apt-get update -q >&2 &&
      as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >&2; }
}

setup_mesa() {
  local missing=() pkg
  command -v dpkg-query >/dev/null || return 0 # not Debian: Mesa is the user's business
  for pkg in "${debian_packages[@]}"; do
    installed "$pkg" || missing+=("$pkg")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    say "installing ${missing[*]}"
    apt_install "${missing[@]}"
  fi
}

# True when the venv has every pinned package at its pinned version.
venv_complete() {
  [ -x "$venv/bin/python" ] || return 1
  "$venv/bin/python" - "${python_packages[@]}" <<'EOF' 2>/dev/null
import sys
from importlib.metadata import version, PackageNotFoundError
for pin in sys.argv[1:]:
    name, wanted = pin.split("==")
    try:
        if version(name) != wanted:
            sys.exit(1)
    except PackageNotFoundError:
        sys.exit(1)
EOF
}

setup_venv() {
  venv_complete && return 0
  if [ ! -x "$venv/bin/python" ]; then
    if ! "$python" -c 'import ensurepip, venv' 2>/dev/null; then
      say "installing python3-venv"
      apt_install python3-venv
    fi
    say "creating $venv"
    mkdir -p "$(dirname "$venv")"
    "$python" -m venv "$venv"
  fi
  say "installing ${python_packages[*]}"
  "$venv/bin/python" -m pip install -q --disable-pip-version-check "${python_packages[@]}" >&2
}

setup_mesa
setup_venv
if [ "${1:-}" = --setup-only ]; then
  exit 0
fi
exec "$venv/bin/python" "$here/s1_llvmpipe.py" "$@"
