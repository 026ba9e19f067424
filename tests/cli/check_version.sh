#!/bin/sh
# The binary names the commit it was built from (the git_hash of every HDF5 file it writes): a
# build after a commit must restamp it (cmake/write_version.cmake). "-dirty" when tracked files
# differ from HEAD; "unknown" outside a git checkout.
# usage: check_version.sh SOURCE_DIR TUMBLE
src=$1
tumble=$2
if head=$(git -C "$src" rev-parse --short HEAD 2>/dev/null); then
  want=$head
  git -C "$src" diff --quiet HEAD -- || want="$head-dirty"
else
  want=unknown
fi
got=$("$tumble" --version) || exit 1
case "$got" in
  *"($want)"*) echo "tumble --version: $got (source tree: $want)"; exit 0 ;;
esac
echo "tumble --version says '$got' but the source tree is at '$want': the stamp is stale"
exit 1
