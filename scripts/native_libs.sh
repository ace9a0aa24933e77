# Sourced by pack_nuget.sh and update_unity_plugins.sh: where a build keeps libpbf, and how a
# package carries the native libraries.

# find_libpbf LIBDIR: the library the build links as libpbf.so (a build folder can also hold an
# older major's file), else the newest versioned file; empty where there is none.
find_libpbf() {
  local so
  so="$(readlink -f "$1/libpbf.so" 2>/dev/null || true)"
  [ -n "$so" ] && [ -e "$so" ] || so="$(ls "$1"/libpbf.so.*.*.* 2>/dev/null | sort -V | tail -n 1 || true)"
  echo "$so"
}

# copy_stripped LIB DEST: copies a native library and strips it (a .dll where the MinGW-w64 strip
# is installed; else it is copied as it is).
copy_stripped() {
  cp -L "$1" "$2"
  case "$2" in
    *.dll)
      if command -v x86_64-w64-mingw32-strip >/dev/null 2>&1; then
        x86_64-w64-mingw32-strip --strip-unneeded "$2"
      fi
      ;;
    *) strip --strip-unneeded "$2" ;;
  esac
}
