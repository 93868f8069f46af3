#!/usr/bin/env bash
# Starts lcm-spy with the HS-SLAM message types, so every project channel is decoded.
#   tools/lcm-spy.sh [--lcm-url URL] [--build DIR] [extra lcm.spy.Spy args]
# Debian's /usr/bin/lcm-spy cannot be used: it passes -Xincgc, which OpenJDK 17 rejects, and
# liblcm-java does not pull in libjchart2d-java, whose jar Spy needs for its charts.
# URL defaults to $LCM_DEFAULT_URL, else LCM's default udpm://239.255.76.67:7667?ttl=0.
# Types come from DIR/share/java/hsslam_types.jar (DIR defaults to <repo>/build; build it with
# `cmake --build DIR --target hs_lcmtypes_java`). Jar locations can be overridden with the
# environment variables LCM_JAR, JCHART2D_JAR and HS_TYPES_JAR.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"

url="${LCM_DEFAULT_URL:-udpm://239.255.76.67:7667?ttl=0}"
build="$root/build"
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --lcm-url | -l) url="${2:?$1 needs a URL}"; shift 2 ;;
    --lcm-url=*) url="${1#*=}"; shift ;;
    --build) build="${2:?--build needs a directory}"; shift 2 ;;
    -h | --help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) extra+=("$1"); shift ;;
  esac
done

fail() {
  echo "lcm-spy.sh: $1" >&2
  echo "lcm-spy.sh: tools/setup.sh installs what lcm-spy needs (default-jdk-headless," \
    "liblcm-java, libjchart2d-java) and builds the type jar." >&2
  exit 1
}

# First existing file among the arguments (globs allowed); empty if none.
first_file() {
  local f
  for f in "$@"; do
    if [ -f "$f" ]; then
      echo "$f"
      return
    fi
  done
}

command -v java >/dev/null || fail "java not found (Debian package default-jdk-headless)"

# lcm-java.pc records where liblcm-java put lcm.jar; the fixed paths cover a source install.
pc_jar="$(pkg-config --variable=classpath lcm-java 2>/dev/null || true)"
lcm_jar="${LCM_JAR:-$(first_file "$pc_jar" /usr/share/java/lcm.jar /usr/local/share/java/lcm.jar)}"
[ -f "$lcm_jar" ] || fail "lcm.jar not found (Debian package liblcm-java; or set LCM_JAR)"

# jchart2d.jar's manifest Class-Path brings in its Debian dependencies jide-oss and
# xmlgraphics-commons. They must not be listed here: Spy loads every class of every jar on -cp
# while looking for types, and theirs fail to load (JDK 17 module checks, commons-io missing).
jchart_jar="${JCHART2D_JAR:-$(first_file /usr/share/java/jchart2d.jar /usr/share/java/jchart2d-*.jar \
  /usr/local/share/java/jchart2d*.jar)}"
[ -f "$jchart_jar" ] || fail "jchart2d.jar not found (Debian package libjchart2d-java; or set JCHART2D_JAR)"

types_jar="${HS_TYPES_JAR:-$build/share/java/hsslam_types.jar}"
[ -f "$types_jar" ] || fail "$types_jar not found: run \
'cmake --build $build --target hs_lcmtypes_java' (needs javac and lcm.jar at configure time)"

# IPv4 because LCM's UDP multicast provider joins an IPv4 group.
exec java -Djava.net.preferIPv4Stack=true \
  -cp "$lcm_jar:$jchart_jar:$types_jar" lcm.spy.Spy --lcm-url="$url" "${extra[@]}"
