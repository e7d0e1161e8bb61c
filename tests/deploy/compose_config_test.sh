#!/usr/bin/env bash
# docker/compose.yaml parses and agrees with docker/Dockerfile and docker/nginx-grpc.conf
# (tests/deploy/check_compose.py). Skips (exit code 77) without a python3 that has PyYAML
# (Debian: python3-yaml).
#   usage: compose_config_test.sh [REPO_ROOT]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=${1:-$(cd "$here/../.." && pwd)}
# shellcheck source=tests/deploy/test_lib.sh
source "$here/test_lib.sh"
python=$(python_with yaml) || skip "no python3 with PyYAML (apt-get install python3-yaml)"
exec "$python" "$here/check_compose.py" "$root"
