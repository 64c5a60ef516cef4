#!/usr/bin/env bash
# deploy/install.sh: installs the Debian 12 packages rollwear needs and builds
# it (Release, CMake + Ninja, -j2) into ./build of the repository.
#
#   bash deploy/install.sh               # packages, then the rollwear binary
#   bash deploy/install.sh --tests       # packages, then everything: the
#                                        # binary, the tests, the benchmarks
#   bash deploy/install.sh --deps-only   # packages only (needs root or sudo)
#   bash deploy/install.sh --build-only  # build only (packages already there;
#                                        # with --tests: everything)
#
# The main job (README) needs only the binary; the tests command adds
# --tests and builds the rest into the same tree, reusing what is built.
#
# Idempotent: packages that are already installed are left alone and an
# existing ./build is reconfigured and built incrementally. Works from any
# directory: it changes to the repository root found from its own path.
# Installs nothing but Debian packages.
#
# Environment:
#   ROLLWEAR_BUILD_DIR   build directory, relative to the repo root (build)
#   ROLLWEAR_JOBS        parallel build jobs (2: the machines have 2 cores)
#   ROLLWEAR_CMAKE_ARGS  extra arguments for the CMake configure step
#   ROLLWEAR_APT_ALWAYS  1 = run apt-get update/install even when every
#                        package is already installed
set -euo pipefail

# Debian packages rollwear builds and tests against. libceres-dev depends on
# (and so brings) libgoogle-glog-dev, libgflags-dev, libsuitesparse-dev and
# libatlas-base-dev, which its CMake config links; nothing the build needs is
# only a "Recommends", so --no-install-recommends is safe.
readonly PACKAGES=(
  build-essential
  g++
  cmake
  ninja-build
  pkg-config
  libeigen3-dev
  libceres-dev
  libsqlite3-dev
  sqlite3
  libspdlog-dev
  libcpp-httplib-dev
  nlohmann-json3-dev
  libsimdjson-dev
  libcli11-dev
  libgtest-dev
  libgmock-dev
  libbenchmark-dev
  chromium
  python3-yaml
  python3-jsonschema
  python3-openpyxl
)

usage() {
  sed -n '2,25s/^# \{0,1\}//p' "${BASH_SOURCE[0]}"
}

log() { printf '[install] %s\n' "$*"; }
die() { printf '[install] error: %s\n' "$*" >&2; exit 1; }

do_deps=1
do_build=1
build_all=0
for arg in "$@"; do
  case "${arg}" in
    --deps-only) do_build=0 ;;
    --tests) build_all=1 ;;
    --build-only) do_deps=0 ;;
    -h | --help) usage; exit 0 ;;
    *) usage >&2; die "unknown option '${arg}'" ;;
  esac
done
if [[ ${do_deps} -eq 0 && ${do_build} -eq 0 ]]; then
  die "--deps-only and --build-only exclude each other"
fi

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "${repo_root}"
build_dir="${ROLLWEAR_BUILD_DIR:-build}"
jobs="${ROLLWEAR_JOBS:-2}"

# Prints the packages of PACKAGES that are not installed, space separated.
missing_packages() {
  local pkg status missing=()
  for pkg in "${PACKAGES[@]}"; do
    status="$(dpkg-query -W -f='${db:Status-Status}' "${pkg}" 2>/dev/null || true)"
    [[ "${status}" == "installed" ]] || missing+=("${pkg}")
  done
  printf '%s' "${missing[*]}"
}

install_deps() {
  command -v apt-get >/dev/null 2>&1 ||
    die "apt-get not found: this script targets Debian 12 (bookworm)"
  if [[ -r /etc/os-release ]]; then
    # shellcheck disable=SC1091
    . /etc/os-release
    if [[ "${ID:-}" != "debian" || "${VERSION_ID:-}" != "12" ]]; then
      log "warning: tested on Debian 12; this is ${PRETTY_NAME:-unknown}"
    fi
  fi
  local sudo=()
  if [[ "$(id -u)" -ne 0 ]]; then
    command -v sudo >/dev/null 2>&1 ||
      die "installing packages needs root (or sudo); run as root"
    sudo=(sudo)
  fi
  local missing
  missing="$(missing_packages)"
  if [[ -z "${missing}" && "${ROLLWEAR_APT_ALWAYS:-0}" != 1 ]]; then
    log "all ${#PACKAGES[@]} Debian packages already installed"
    return
  fi
  log "installing Debian packages (missing: ${missing:-none})"
  local apt=("${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get
             -o DPkg::Lock::Timeout=600 -q)
  "${apt[@]}" update
  "${apt[@]}" install -y --no-install-recommends "${PACKAGES[@]}"
  missing="$(missing_packages)"
  [[ -z "${missing}" ]] || die "still missing after install: ${missing}"
  log "Debian packages installed"
}

build() {
  if ! command -v cmake >/dev/null 2>&1 || ! command -v ninja >/dev/null 2>&1; then
    die "cmake/ninja not found: run 'bash deploy/install.sh --deps-only' first"
  fi
  # A build dir configured with another generator cannot be reused by CMake;
  # drop its cache (build outputs only, never sources).
  local cache="${build_dir}/CMakeCache.txt"
  if [[ -f "${cache}" ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "${cache}"; then
    log "${build_dir} was configured with another generator; reconfiguring"
    rm -rf "${cache}" "${build_dir}/CMakeFiles"
  fi
  local extra=()
  if [[ -n "${ROLLWEAR_CMAKE_ARGS:-}" ]]; then
    read -r -a extra <<<"${ROLLWEAR_CMAKE_ARGS}"
  fi
  log "configuring ${repo_root}/${build_dir} (Release, Ninja)"
  cmake -S . -B "${build_dir}" -G Ninja \
    -DCMAKE_BUILD_TYPE=Release \
    -DROLLWEAR_SANITIZE=OFF \
    -DROLLWEAR_BUILD_TESTS=ON \
    -DROLLWEAR_BUILD_BENCH=ON \
    "${extra[@]}"
  local target=(--target rollwear)
  [[ ${build_all} -eq 1 ]] && target=()
  log "building $([[ ${build_all} -eq 1 ]] && echo 'everything (binary, tests, benchmarks)' || echo 'the rollwear binary') with ${jobs} jobs"
  local start=${SECONDS}
  cmake --build "${build_dir}" --parallel "${jobs}" "${target[@]}"
  log "build finished in $((SECONDS - start)) s"
  local bin="${repo_root}/${build_dir}/service/rollwear"
  [[ -x "${bin}" ]] || die "build finished but ${bin} is missing"
  log "binary: ${bin}"
  if [[ ${build_all} -eq 1 ]]; then
    log "next:   ctest --test-dir ${build_dir} --output-on-failure -j2"
  else
    log "next:   bash deploy/demo.sh   (tests: bash deploy/install.sh --tests)"
  fi
}

if [[ ${do_deps} -eq 1 ]]; then install_deps; fi
if [[ ${do_build} -eq 1 ]]; then build; fi
