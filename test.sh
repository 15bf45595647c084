#!/usr/bin/env bash
# The README's test command: installs what the tests need when it is missing, then runs
# `cargo test --workspace`. Arguments replace `--workspace` (e.g. `./test.sh -p usar-world`).
#
# What the tests need beyond a Rust toolchain:
# - Debian's headless Chromium and its WebDriver (`chromium`, `chromium-driver`), for the
#   operator console's end-to-end browser test (crates/usar-console/tests/browser.rs);
# - a Python virtual environment (target/py-venv) with the MCAP project's readers `mcap` and
#   `mcap-ros2-support` and `rosbags` (the recording and log interop tests,
#   crates/usar-record/tests/, crates/usar-log/tests/), Eclipse Cyclone DDS's `cyclonedds`
#   (the ROS 2 bridge's interop test, crates/usar-ros2/tests/) and the laser reference's raycast2D,
#   OpenCV and NumPy (crates/usar-bench/tests/); its interpreter is passed to the tests as
#   USAR_PYTHON.
#
# Set USAR_FUZZ_SECONDS to let the loaders' fuzz harness run longer than its CI budget.
set -euo pipefail
cd "$(dirname "$0")"

need_apt=()
[ -x /usr/bin/chromium ] || need_apt+=(chromium)
[ -x /usr/bin/chromedriver ] || need_apt+=(chromium-driver)
if [ ${#need_apt[@]} -gt 0 ]; then
  if ! command -v apt-get >/dev/null; then
    echo "test.sh: ${need_apt[*]} missing and no apt-get here: install Chromium and chromedriver at /usr/bin" >&2
    exit 1
  fi
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "test.sh: installing ${need_apt[*]} needs root or sudo" >&2; exit 1; }
    SUDO="sudo"
  fi
  echo "test.sh: installing ${need_apt[*]} (the console's browser test)"
  # Two tries: a mirror hiccup should not fail the run.
  for try in 1 2; do
    if $SUDO apt-get update -qq &&
      DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need_apt[@]}"; then
      break
    fi
    if [ "$try" -eq 2 ]; then
      echo "test.sh: could not install ${need_apt[*]}" >&2
      exit 1
    fi
    sleep 10
  done
fi

# Independent readers of our MCAP recordings and the laser reference, pinned.
VENV="$PWD/target/py-venv"
PY_PACKAGES=(mcap==1.6.0 mcap-ros2-support==0.6.0 rosbags==0.11.9 cyclonedds==11.0.1
  raycast2D==0.2.0 opencv-python-headless==5.1.0.95 numpy==2.4.6)
if ! "$VENV/bin/python" -c 'import mcap, mcap_ros2, rosbags, cyclonedds, raycast2D, cv2, numpy' 2>/dev/null; then
  echo "test.sh: installing ${PY_PACKAGES[*]} into $VENV (the Python interop tests)"
  python3 -m venv "$VENV"
  for try in 1 2; do
    if "$VENV/bin/pip" install -q "${PY_PACKAGES[@]}"; then
      break
    fi
    if [ "$try" -eq 2 ]; then
      echo "test.sh: could not install ${PY_PACKAGES[*]}" >&2
      exit 1
    fi
    sleep 10
  done
fi
export USAR_PYTHON="$VENV/bin/python"

if [ $# -eq 0 ]; then
  exec cargo test --workspace
fi
exec cargo test "$@"
