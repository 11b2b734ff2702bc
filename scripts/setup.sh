#!/usr/bin/env bash
# Set up contact_sim from nothing, in this checkout:
#   1. a virtual environment in .venv (the venv root doubles as the ament prefix),
#   2. the pinned ROS 2 Kilted wheels, numpy/scipy, the test and build tools,
#   3. the package itself, editable (source edits take effect without reinstalling),
#   4. a `colcon build --symlink-install` into the venv, so that
#      ament_index_python.get_package_prefix("contact_sim") resolves to .venv and
#      .venv/lib/contact_sim/ holds the executables, as `ros2 run` expects,
#   5. `source .venv/bin/activate` then also sets AMENT_PREFIX_PATH and puts
#      .venv/lib/contact_sim (the executables: contact_sim_node, contact_sim_record, contact-sim)
#      on PATH; `deactivate` puts both back, and activating twice adds nothing twice.
# Re-running it is safe and quick.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$(pwd)
python=${PYTHON:-python3}

if [ ! -x .venv/bin/python ]; then
    "$python" -m venv .venv
fi
.venv/bin/python -m pip install --quiet -c constraints.txt -r requirements.txt
.venv/bin/python -m pip install --quiet --no-deps --no-build-isolation -e .

# The ament prefix: the venv root. colcon writes the resource-index marker, share/contact_sim
# and the lib/contact_sim executables (symlinked to this source tree) there.
(
    export VIRTUAL_ENV="$root/.venv" PATH="$root/.venv/bin:$PATH"
    unset AMENT_PREFIX_PATH
    unset COLCON_PREFIX_PATH
    colcon --log-base build/log build --symlink-install --merge-install \
        --install-base .venv --build-base build --base-paths . \
        --event-handlers console_direct- summary- >/dev/null
)

marker='# contact_sim activation hook v4'
if ! grep -qF "$marker" .venv/bin/activate; then
    # drop an older hook (it is the end of the file), then append this one
    sed -i '/^# contact_sim activation hook/,$d' .venv/bin/activate
    cat >> .venv/bin/activate <<'HOOK'
# contact_sim activation hook v4
# contact_sim: ament prefix (the venv root is where ROS tools look for packages), and the
# package's executables, in <prefix>/lib/contact_sim where `ros2 run` looks for them.
# `deactivate` puts AMENT_PREFIX_PATH back as it was (PATH is the venv's own job); activating
# again first deactivates, so nothing is added twice.
if [ -n "${_CONTACT_SIM_ACTIVE:-}" ]; then   # activated again: start from the saved value
    if [ -n "${_CONTACT_SIM_HAD_AMENT_PREFIX_PATH:-}" ]; then
        AMENT_PREFIX_PATH="$_CONTACT_SIM_OLD_AMENT_PREFIX_PATH"
    else
        unset AMENT_PREFIX_PATH
    fi
fi
_CONTACT_SIM_ACTIVE=1
_CONTACT_SIM_OLD_AMENT_PREFIX_PATH="${AMENT_PREFIX_PATH:-}"
_CONTACT_SIM_HAD_AMENT_PREFIX_PATH="${AMENT_PREFIX_PATH+1}"
eval "_contact_sim_venv_$(declare -f deactivate)"
deactivate () {
    if [ -n "${_CONTACT_SIM_HAD_AMENT_PREFIX_PATH:-}" ]; then
        AMENT_PREFIX_PATH="$_CONTACT_SIM_OLD_AMENT_PREFIX_PATH"
        export AMENT_PREFIX_PATH
    else
        unset AMENT_PREFIX_PATH
    fi
    unset _CONTACT_SIM_OLD_AMENT_PREFIX_PATH _CONTACT_SIM_HAD_AMENT_PREFIX_PATH _CONTACT_SIM_ACTIVE
    _contact_sim_venv_deactivate "$@"
    if [ "${1:-}" != "nondestructive" ]; then
        unset -f _contact_sim_venv_deactivate deactivate
    fi
}
AMENT_PREFIX_PATH="$VIRTUAL_ENV${AMENT_PREFIX_PATH:+:$AMENT_PREFIX_PATH}"
PATH="$VIRTUAL_ENV/lib/contact_sim:$PATH"
export AMENT_PREFIX_PATH PATH
HOOK
fi
# numba's cache: cleared if a source it compiles from changed since it was stamped (numba checks a
# kernel's own file only: scripts/numba_cache.py); then the node's kernels compiled once, running
# its engine as it does (contact_sim.ros.precompile), and cached in contact_sim/**/__pycache__
.venv/bin/python scripts/numba_cache.py
.venv/bin/python -m contact_sim.ros.precompile
echo "contact_sim is set up: source .venv/bin/activate"
