# Sourced by scripts/build.sh and scripts/test.sh: the build environment they share.
# ccache keys on paths relative to the checkout, so a fresh clone reuses earlier compilations;
# pch_defines and time_macros let it cache the tests' precompiled headers and what uses them.
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=true CCACHE_SLOPPINESS=pch_defines,time_macros

# The generator for build folder $1: Ninja for a new folder when installed (it schedules the
# whole build at once; scripts/install-deps.sh installs it), else whatever the folder has.
capz_generator() {
  if [ ! -f "$1/CMakeCache.txt" ] && command -v ninja >/dev/null 2>&1; then
    echo "-G Ninja"
  fi
}
