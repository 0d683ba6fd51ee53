#!/usr/bin/env bash
# Starts lcm-spy with codesign's message types (build/release/codesign_lcm_types.jar), so the
# channels CODESIGN_SIM_STEP, CODESIGN_TRAIN_STEP, CODESIGN_EPISODE, CODESIGN_PPO and
# CODESIGN_DISTRIBUTION show every field with a live plot. See docs/telemetry.md.
#
#   bash scripts/spy.sh [LCM_URL]          default tcpq://127.0.0.1:7700
#
# Debian 12's /usr/bin/lcm-spy does not start on Java 17 (it passes -Xincgc) and ignores
# CLASSPATH, so the class is started directly. Needs default-jre-headless, liblcm-java and
# libjchart2d-java (without jchart2d lcm-spy cannot plot), and a built types jar
# (bash scripts/setup.sh, or CODESIGN_LCM_JAR=/path/to/codesign_lcm_types.jar).
#
# Ways to watch a run:
#   Workstation (multicast on this host only):
#       bash scripts/spy.sh 'udpm://239.255.76.67:7667?ttl=0'
#       run with the same URL (udpm needs a multicast route, e.g. on lo:
#       sudo ip route add 224.0.0.0/4 dev lo)
#   Loopback TCP, no multicast (servers, containers):
#       java -cp /usr/share/java/lcm.jar lcm.lcm.TCPService 7700 &
#       bash scripts/spy.sh                     # = tcpq://127.0.0.1:7700
#       run with tcpq://127.0.0.1:7700
#   Record and replay:
#       lcm-logger --lcm-url='udpm://239.255.76.67:7667?ttl=0' run.lcm   # or the run writes
#                                                # file:///abs/path/run.lcm?mode=w itself
#       lcm-logplayer --lcm-url='udpm://239.255.76.67:7667?ttl=0' run.lcm   # while spy.sh listens
#       bash scripts/spy.sh 'file:///abs/path/run.lcm?speed=1'              # or read the log directly
set -euo pipefail
cd "$(dirname "$0")/.."

URL="${1:-tcpq://127.0.0.1:7700}"
JAR="${CODESIGN_LCM_JAR:-build/release/codesign_lcm_types.jar}"
if [ ! -f "$JAR" ]; then
  echo "spy: $JAR not found: build first (bash scripts/setup.sh) or set CODESIGN_LCM_JAR" >&2
  exit 2
fi
[ -f /usr/share/java/jchart2d.jar ] ||
  echo "spy: warning: /usr/share/java/jchart2d.jar missing (apt-get install libjchart2d-java): no plots" >&2

exec java -Djava.net.preferIPv4Stack=true -Xmx256m \
  -cp "/usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar:$JAR" \
  lcm.spy.Spy -l "$URL"
