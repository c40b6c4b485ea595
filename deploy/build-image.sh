#!/usr/bin/env bash
# Builds the ddsimp-server container image from deploy/Dockerfile, also where Docker Hub cannot be
# reached and no Docker engine runs.
#
#   deploy/build-image.sh [-t TAG] [--jobs N] [--base-only] [--rebuild-base]
#   deploy/build-image.sh --print-run-command      (`podman run` with what it needs here)
#
# - A running Docker engine (`docker info` answers): `docker build`, base images pulled as usual.
# - Otherwise Podman (Debian: apt-get install podman runc debuerreotype). The base images
#   debian:bookworm and debian:bookworm-slim come from the local image store; when they are
#   not there and cannot be pulled, they are made here from Debian's mirror with debuerreotype,
#   the tool that makes the official Debian images (minbase, the same minimizing configuration,
#   slimify for -slim), and imported under those names. The build then never pulls.
# - Where the default OCI runtime cannot start a container (crun refuses a hybrid cgroup
#   hierarchy, podman's default open-file limit above the host's hard limit), the build uses
#   runc and the host's limits; the probe says which, and --print-run-command prints the
#   command to run the image with: `$(deploy/build-image.sh --print-run-command) ... ddsimp-server`.
#
# Environment: DDSIMP_IMAGE_ENGINE=docker|podman to choose, DDSIMP_DEBIAN_SUITE (bookworm);
# NODE_EXTRA_CA_CERTS, a file of CA certificates that npm must trust in the web stage (a proxy
# that intercepts TLS), passed as the build secret npm_ca.
# Must run as root for the base images (debootstrap); the build itself also works rootless.
set -euo pipefail

tag=ddsimp-server:latest
jobs=2
base_only=0
rebuild_base=0
print_run_command=0
while [[ $# -gt 0 ]]; do
    case "$1" in
    -t | --tag) tag=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --base-only) base_only=1; shift ;;
    --rebuild-base) rebuild_base=1; shift ;;
    --print-run-command) print_run_command=1; shift ;;
    -h | --help) sed -n '2,22s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) echo "build-image.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
done

root=$(cd "$(dirname "$0")/.." && pwd)
suite=${DDSIMP_DEBIAN_SUITE:-bookworm}
say() { printf 'build-image.sh: %s\n' "$*" >&2; }

engine=${DDSIMP_IMAGE_ENGINE:-}
if [[ -z $engine ]]; then
    if command -v docker >/dev/null && docker info >/dev/null 2>&1; then
        engine=docker
    elif command -v podman >/dev/null; then
        engine=podman
    else
        say "neither a running Docker engine nor podman; install podman (apt-get install podman runc)"
        exit 1
    fi
fi
say "engine: $engine"

if [[ ! -f $root/web/package.json ]]; then
    say "web/package.json is missing: the image's web stage builds the renderer from web/"
    exit 1
fi

build_options=(--build-arg "JOBS=$jobs")
if [[ -n ${NODE_EXTRA_CA_CERTS:-} && -s $NODE_EXTRA_CA_CERTS ]]; then
    say "npm in the web stage trusts $NODE_EXTRA_CA_CERTS (build secret npm_ca)"
    build_options+=(--secret "id=npm_ca,src=$NODE_EXTRA_CA_CERTS")
fi

if [[ $engine == docker ]]; then
    [[ $base_only == 1 ]] && exit 0
    exec nice docker build "${build_options[@]}" -f "$root/deploy/Dockerfile" -t "$tag" "$root"
fi

# --- podman: base images ------------------------------------------------------------------------
base_full=docker.io/library/debian:$suite
base_slim=docker.io/library/debian:$suite-slim

make_base_images() {
    local missing=()
    for tool in debuerreotype-init debootstrap; do
        command -v "$tool" >/dev/null || missing+=("$tool")
    done
    if [[ ${#missing[@]} -gt 0 ]]; then
        say "cannot make the base images: ${missing[*]} not found (apt-get install debuerreotype debootstrap)"
        exit 1
    fi
    local work
    work=$(mktemp -d "${TMPDIR:-/var/tmp}/ddsimp-base.XXXXXX")
    # shellcheck disable=SC2064 # expand $work now
    trap "rm -rf '$work'" EXIT
    say "making $base_full and $base_slim in $work from http://deb.debian.org/debian"
    # --non-debian: from deb.debian.org instead of snapshot.debian.org (often unreachable);
    # the Release file's date is the rootfs's epoch. debootstrap checks the archive's signature.
    nice debuerreotype-init --non-debian "$work/rootfs" "$suite" http://deb.debian.org/debian
    debuerreotype-minimizing-config "$work/rootfs"
    # The official images' sources (debuerreotype-debian-sources-list would ask snapshot.debian.org).
    rm -f "$work/rootfs/etc/apt/sources.list"
    cat >"$work/rootfs/etc/apt/sources.list.d/debian.sources" <<SOURCES
Types: deb
URIs: http://deb.debian.org/debian
Suites: $suite $suite-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: http://deb.debian.org/debian-security
Suites: $suite-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SOURCES
    debuerreotype-apt-get "$work/rootfs" update -qq
    debuerreotype-apt-get "$work/rootfs" dist-upgrade -yqq
    debuerreotype-tar "$work/rootfs" "$work/full.tar"
    cp -a "$work/rootfs" "$work/slim"
    debuerreotype-slimify "$work/slim"
    debuerreotype-tar "$work/slim" "$work/slim.tar"
    podman import --change 'CMD ["bash"]' "$work/full.tar" "$base_full" >/dev/null
    podman import --change 'CMD ["bash"]' "$work/slim.tar" "$base_slim" >/dev/null
    rm -rf "$work"
    trap - EXIT
}

have_base_images() {
    podman image exists "$base_full" && podman image exists "$base_slim"
}

if [[ $rebuild_base == 1 ]] || ! have_base_images; then
    if [[ $rebuild_base == 0 ]] && podman pull -q "$base_full" >/dev/null 2>&1 &&
        podman pull -q "$base_slim" >/dev/null 2>&1; then
        say "pulled $base_full and $base_slim"
    else
        [[ $rebuild_base == 1 ]] || say "cannot pull $base_full: making it locally"
        make_base_images
    fi
fi
podman images --format '{{.Repository}}:{{.Tag}} {{.Size}}' --filter "reference=$base_full" \
    --filter "reference=$base_slim" >&2
[[ $base_only == 1 ]] && exit 0

# --- podman: which runtime options start a container here ----------------------------------------
runtime_options=() # podman's global options
run_options=()     # options of podman run and podman build
probe_run_options() {
    local err
    err=$(mktemp)
    if podman run --rm --pull=never "$base_slim" true 2>"$err"; then
        rm -f "$err"
        return
    fi
    say "a container does not start with podman's defaults: $(tail -n 1 "$err")"
    rm -f "$err"
    # podman caps RLIMIT_NPROC at 32768 for the runtime it starts; crun refuses hybrid cgroups.
    local nproc_limit nofile_limit
    nproc_limit=$(ulimit -Hu)
    nofile_limit=$(ulimit -Hn)
    [[ $nproc_limit == unlimited || $nproc_limit -gt 32768 ]] && nproc_limit=32768
    [[ $nofile_limit == unlimited || $nofile_limit -gt 1048576 ]] && nofile_limit=1048576
    run_options=(--ulimit "nofile=$nofile_limit:$nofile_limit" --ulimit "nproc=$nproc_limit:$nproc_limit")
    command -v runc >/dev/null && runtime_options=(--runtime runc)
    if ! podman "${runtime_options[@]}" run --rm --pull=never "${run_options[@]}" "$base_slim" true; then
        say "no container starts here, not even with ${runtime_options[*]} ${run_options[*]} (is runc installed?)"
        exit 1
    fi
    say "containers start with: podman ${runtime_options[*]} run ${run_options[*]}"
}
probe_run_options
if [[ $print_run_command == 1 ]]; then
    echo "podman ${runtime_options[*]} run ${run_options[*]}"
    exit 0
fi

# --- podman: the image -----------------------------------------------------------------------------
say "building $tag (cmake -j$jobs)"
# --format docker: the OCI image format has no HEALTHCHECK (podman would drop it with a warning).
nice podman "${runtime_options[@]}" build --pull=never --format docker "${run_options[@]}" \
    "${build_options[@]}" -f "$root/deploy/Dockerfile" -t "$tag" "$root"
podman images --format '{{.Repository}}:{{.Tag}} {{.Size}}' --filter "reference=$tag" >&2
