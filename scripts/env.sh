# Source this to use pdbfs's environment: the active virtual environment, or
# the project's .venv that scripts/setup.sh made.
if [ -z "${VIRTUAL_ENV:-}" ] && [ -x "$(dirname "${BASH_SOURCE[0]}")/../.venv/bin/python" ]; then
    source "$(dirname "${BASH_SOURCE[0]}")/../.venv/bin/activate"
fi
