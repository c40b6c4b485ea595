#!/usr/bin/env bash
# Usage: check-dockerfile.sh ROOT SERVER_BINARY
# What can be checked of deploy/Dockerfile without building the image (deploy/build-image.sh
# does that; too heavy for the test suite):
# - every shared library the built ddsimp-server links comes, on this Debian machine, from a
#   package that the runtime stage installs or that the base image has, so the server starts in
#   the image. "Has" is approximated from above by apt: the dependencies, recursively, of the
#   packages the stage installs and of the essential and required ones (minbase, which is what
#   debian:bookworm-slim holds), every alternative of an "a | b" dependency included;
# - the runtime stage installs no compiler, build tool, -dev package, VTK, Qt or Node.js;
# - it runs as a user other than root, has a HEALTHCHECK on /healthz and an ENTRYPOINT;
# - every file the Dockerfile copies from the build context exists.
set -euo pipefail
root=$1
server=$2
dockerfile=$root/deploy/Dockerfile
failures=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}

# The runtime stage: from its FROM line to the end, continuation lines joined.
runtime=$(sed -n '/^FROM .* AS runtime/,$p' "$dockerfile" | sed -e ':a' -e '/\\$/N; s/\\\n//; ta')
[[ -n $runtime ]] || { echo "FAIL: no 'FROM ... AS runtime' stage in $dockerfile" >&2; exit 1; }
# Package names after "apt-get install" in the runtime stage (options and shell operators cut).
installed=$(grep -o 'apt-get install[^&;]*' <<<"$runtime" | sed 's/apt-get install//' |
    tr -s ' ' '\n' | grep -v '^-' | grep -v '^$' | sort -u || true)
[[ -n $installed ]] || fail "the runtime stage installs no packages"
echo "runtime stage installs: $(echo "$installed" | xargs)"

# 1. The server's libraries.
package_of() { # the Debian package holding a file, with or without /usr (merged /usr)
    local path=$1 other
    case "$path" in
    /usr/*) other=${path#/usr} ;;
    *) other=/usr$path ;;
    esac
    { dpkg -S "$path" 2>/dev/null || dpkg -S "$other" 2>/dev/null; } | head -n 1 | sed 's/[:,].*//'
}
roots=$(dpkg-query -W -f '${Package} ${Essential} ${Priority}\n' | awk '$2 == "yes" || $3 == "required" {print $1}')
# shellcheck disable=SC2086 # word splitting wanted: package names
available=$(apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks \
    --no-replaces --no-enhances $installed $roots | grep -v -e '^ ' -e '^<' | sed 's/:.*//' | sort -u)
libraries=$(ldd "$server" | awk '$2 == "=>" && $3 ~ /^\// {print $3}')
[[ -n $libraries ]] || fail "ldd found no shared libraries in $server"
for library in $libraries; do
    package=$(package_of "$library")
    if [[ -z $package ]]; then
        fail "$library (linked by ddsimp-server) belongs to no Debian package here"
        continue
    fi
    if grep -qx "$package" <<<"$installed"; then
        echo "ok: $library from $package (installed by the runtime stage)"
    elif grep -qx "$package" <<<"$available"; then
        echo "ok: $library from $package (a dependency, or in the base image)"
    else
        fail "$library comes from $package, which the runtime stage does not install"
    fi
done

# 2. Nothing to build with in the runtime stage.
for package in $installed; do
    case "$package" in
    build-essential | gcc* | g++* | clang* | cmake* | ninja-build | make | pkg-config | \
        *-dev | libvtk* | vtk* | *qt* | nodejs | npm)
        fail "the runtime stage installs $package" ;;
    esac
done
if grep -Eq '^COPY --from=build /(usr|build)/?( |$)' <<<"$runtime"; then
    fail "the runtime stage copies a whole tree from the build stage"
fi

# 3. User, health check, entry point.
user=$(grep -E '^USER ' <<<"$runtime" | tail -n 1 | awk '{print $2}')
case "$user" in
"" | root | 0 | 0:*) fail "the runtime stage runs as root (USER '${user:-unset}')" ;;
*) echo "ok: runs as $user" ;;
esac
grep -Eq '^HEALTHCHECK .*CMD .*/healthz' <<<"$runtime" || fail "no HEALTHCHECK on /healthz"
grep -Eq '^ENTRYPOINT \[' <<<"$runtime" || fail "no exec-form ENTRYPOINT"

# 4. The build context's files that the Dockerfile copies.
while read -r source; do
    [[ -e $root/$source ]] || fail "COPY $source: no such file in the build context"
done < <(grep -E '^COPY ' "$dockerfile" | grep -v -- '--from=' |
    awk '{for (i = 2; i < NF; i++) print $i}' | grep -vx '\.')

if [[ $failures -gt 0 ]]; then
    echo "$failures check(s) of deploy/Dockerfile failed" >&2
    exit 1
fi
echo "deploy/Dockerfile: all checks passed"
