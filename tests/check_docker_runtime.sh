#!/usr/bin/env bash
# Keeps docker/Dockerfile true without a Docker engine: every shared library mocapd loads must come
# from a Debian package the runtime stage installs (or from the base image: libc, libstdc++, libgcc).
set -euo pipefail
root=$1
binary=$2
runtime=$(sed -n '/AS runtime/,$p' "$root/docker/Dockerfile")
missing=0
for lib in $(ldd "$binary" | awk '/=>/ {print $3}'); do
  package=$(dpkg -S "$(readlink -f "$lib")" 2>/dev/null || dpkg -S "$lib" 2>/dev/null || true)
  package=${package%%:*}
  case "$package" in
    libc6|libstdc++6|libgcc-s1|"") continue ;;
  esac
  if ! grep -qw -- "$package" <<<"$runtime"; then
    echo "docker/Dockerfile runtime stage lacks $package (provides $lib)"; missing=1
  fi
done
[ $missing -eq 0 ] && echo "docker runtime packages: ok"
exit $missing
