#!/usr/bin/env bash
# Debian 13's FreeCAD 1.0.0 in a chroot, for the workbench's FreeCAD tests (issue 73): built from Debian's packages
# (debootstrap, then apt inside it; about 8 minutes) and kept between runs in $RULED_FREECAD1_DIR; while CI runs,
# the repository, ../shared and /tmp are bound into it at their own paths, so that the tests' scripts, files and
# FreeCAD's outputs are where the tests look (tests/conftest.py runs each FreeCAD test module in it too).
#
#   bash .ci/freecad1.sh build     # build the chroot where it is missing (a file .ruled-ready marks it complete)
#   bash .ci/freecad1.sh mount     # bind /proc, /sys, /dev, /tmp, the repository and ../shared into it
#   bash .ci/freecad1.sh umount    # and undo that
#   bash .ci/freecad1.sh version   # FreeCAD's version in it
set -euo pipefail
cd "$(dirname "$0")/.."
REPO=$(pwd -P)
SHARED=$(cd .. && pwd -P)/shared
DIR=${RULED_FREECAD1_DIR:-/var/cache/ruled/freecad1}
MIRROR=${RULED_DEBIAN_MIRROR:-http://deb.debian.org/debian}
# FreeCAD, the kernels in its Python (Debian's numba), the GUI under Xvfb with real clicks (PySide2's QtTest)
PACKAGES=(freecad python3-numba python3-scipy xvfb xauth python3-pyside2.qttest)

binds() {       # what is bound into the chroot, in mounting order
  echo /proc /sys /dev /dev/pts /dev/shm /tmp "$REPO"
  [ -d "$SHARED" ] && echo "$SHARED"
  return 0
}

do_mount() {    # root: the chroot's folder
  local root=$1 p
  for p in $(binds); do
    mkdir -p "$root$p"
    mountpoint -q "$root$p" || mount --bind "$p" "$root$p"
  done
}

do_umount() {
  local root=$1 p
  for p in $(binds | tr ' ' '\n' | tac); do
    mountpoint -q "$root$p" && umount -l "$root$p" || true
  done
}

unmounted() {   # refuse to delete a folder with anything still mounted inside it (the repository, /tmp)
  if awk -v p="$1/" 'index($2, p) == 1 { found = 1 } END { exit !found }' /proc/mounts; then
    echo "FreeCAD 1.0 chroot: $1 still has mounts inside it; not deleting it (bash .ci/freecad1.sh umount)"
    exit 1
  fi
}

build() {
  [ -e "$DIR/.ruled-ready" ] && { echo "FreeCAD 1.0 chroot: $DIR (kept)"; return 0; }
  local t0=$SECONDS part="$DIR.partial"
  echo "FreeCAD 1.0 chroot: building $DIR from Debian 13's packages (about 8 minutes, once)"
  if ! command -v debootstrap >/dev/null 2>&1; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq && apt-get install -y -qq debootstrap >/dev/null
  fi
  do_umount "$part" 2>/dev/null || true
  unmounted "$part"
  rm -rf "$part"
  mkdir -p "$(dirname "$DIR")"
  debootstrap --variant=minbase trixie "$part" "$MIRROR" > "$part.log" 2>&1 || { tail -n 30 "$part.log"; exit 1; }
  cp /etc/resolv.conf "$part/etc/resolv.conf" 2>/dev/null || true
  do_mount "$part"
  trap 'do_umount "$part"' EXIT
  chroot "$part" env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  chroot "$part" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "${PACKAGES[@]}" >> "$part.log" 2>&1 || { tail -n 30 "$part.log"; exit 1; }
  chroot "$part" apt-get clean
  do_umount "$part"
  trap - EXIT
  unmounted "$part"
  unmounted "$DIR"
  rm -rf "$DIR"
  mv "$part" "$DIR"
  mv "$part.log" "$DIR/.ruled-build.log"
  touch "$DIR/.ruled-ready"
  echo "FreeCAD 1.0 chroot: built in $((SECONDS - t0)) s"
}

version() {
  printf 'import FreeCAD, os, sys\nprint("FreeCAD " + ".".join(FreeCAD.Version()[:3]) + " in " + %s)\n%s\n' \
    "'$DIR'" "sys.stdout.flush(); os._exit(0)" > "$DIR/tmp/ruled-version.py"
  chroot "$DIR" freecadcmd /tmp/ruled-version.py 2>/dev/null | tail -n 1
}

case "${1:-}" in
  build) build ;;
  mount) [ -e "$DIR/.ruled-ready" ] || { echo "no FreeCAD 1.0 chroot at $DIR: bash .ci/freecad1.sh build"; exit 2; }
         do_mount "$DIR" ;;
  umount) do_umount "$DIR" ;;
  version) version ;;
  *) echo "usage: bash .ci/freecad1.sh build|mount|umount|version"; exit 2 ;;
esac
