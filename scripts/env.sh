# Source this to use pdbfs's environment: the active virtual environment, or
# the project's .venv that scripts/setup.sh made.
if [ -z "${VIRTUAL_ENV:-}" ] && [ -x "$(dirname "${BASH_SOURCE[0]}")/../.venv/bin/python" ]; then
    source "$(dirname "${BASH_SOURCE[0]}")/../.venv/bin/activate"
fi
# MkDocs-Material's end-of-life notice, printed by every docs build, off (CONTRIBUTING.md:
# the documentation stays on MkDocs-Material 9)
export NO_MKDOCS_2_WARNING=1
