#!/bin/bash
# The many-core scaling study (README.md beside this file): runs the cases of scenes.py at
# 1, 2, 4, 8 and 16 ranks with the runtime that collect_runtime.sh gathered (DIR, or DIR.tgz
# unpacked), writes $OUT/results.txt (one line a run) and $OUT/logs.tgz.
# CASES (default "A C D M E B") chooses the cases; E needs E_CKPT, the collapse's checkpoint
# (a .gz is unpacked), and E_STEP0, its step; E_BALANCES the splits it compares (default
# "cells points"). RANKS and NIND (independent runs of D) as below; BIN another binary.
set -u
S=$(cd "$(dirname "$0")" && pwd); R=${1:-$S/.devrt}
[ -d "$R" ] || { mkdir -p "$R" && tar xzf "$R.tgz" -C "$(dirname "$R")"; }
R=$(cd "$R" && pwd)
W=/tmp/scale; mkdir -p $W; cd $W
export LD_LIBRARY_PATH=$R/lib:/usr/lib/x86_64-linux-gnu/openmpi/lib
if [ ! -e /usr/lib/x86_64-linux-gnu/openmpi ]; then
  cp -a $R/ompi/openmpi /usr/lib/x86_64-linux-gnu/openmpi
  [ -e /usr/share/openmpi ] || cp -a $R/ompi/share-openmpi /usr/share/openmpi
  [ -e /etc/openmpi ] || cp -a $R/ompi/etc-openmpi /etc/openmpi
else
  mkdir -p /opt/dpmpi/usr/lib/x86_64-linux-gnu /opt/dpmpi/usr/share
  cp -a $R/ompi/openmpi /opt/dpmpi/usr/lib/x86_64-linux-gnu/openmpi; cp -a $R/ompi/share-openmpi /opt/dpmpi/usr/share/openmpi
  export OPAL_PREFIX=/opt/dpmpi/usr LD_LIBRARY_PATH=$R/lib:/opt/dpmpi/usr/lib/x86_64-linux-gnu/openmpi/lib
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
MPIRUN=$R/bin/orterun; BIN=${BIN:-$R/bin/dpmpm}; RES=$OUT/results.txt
if [ -n "${E_CKPT:-}" ] && [ "${E_CKPT%.gz}" != "$E_CKPT" ]; then gunzip -c "$E_CKPT" > $W/flow.ckpt.h5; E_CKPT=$W/flow.ckpt.h5; fi
export E_CKPT=${E_CKPT:-}
{ echo "# $(date -u) nproc=$(nproc) $($BIN --version 2>/dev/null | head -1)"; lscpu | grep -E 'Model name|^CPU\(s\)|Thread|Core|Socket|NUMA node|L2|L3' ; free -g | head -2; } >> $RES
python3 $S/scenes.py $W/scn
BIND="--bind-to core --map-by core"
$MPIRUN -n 16 $BIND hostname > probe.log 2>&1 || BIND="--bind-to none"
$MPIRUN -n 16 $BIND hostname >> probe.log 2>&1 || { BIND="--bind-to none --oversubscribe"; echo "# oversubscribe" >> $RES; }
echo "# bind: $BIND" >> $RES; sort probe.log | uniq -c | head -5 >> $RES
tps() { grep -o 'time per step [0-9.]* ms over [0-9]* steps' "$1" | awk '{print $4*$7}'; }
one() {  # case ranks -> per-step ms from the 5- and 25-step runs
  local c=$1 r=$2
  for s in 5 25; do timeout 200 $MPIRUN -n $r $BIND $BIN scn/${c}_${r}_${s}.nml > log_${c}_${r}_${s}.txt 2>&1 </dev/null; done
  local a b; a=$(tps log_${c}_${r}_5.txt); b=$(tps log_${c}_${r}_25.txt)
  echo "$c ranks=$r ms_per_step=$(python3 -c "print(round(($b-$a)/20,3))" 2>/dev/null || echo fail) $(grep -o '[0-9]* solid points; per rank min [0-9]* max [0-9]*' log_${c}_${r}_25.txt | head -1) $(grep -o 'busiest rank holds [0-9]* points, the mean is [0-9]*' log_${c}_${r}_25.txt | tail -1) $(grep -o 'time in [a-z0-9_]* *[0-9.]* s' log_${c}_${r}_25.txt | tr -s ' ' | tr '\n' ';')" >> $RES
}
RANKS=${RANKS:-1 2 4 8 16}; NIND=${NIND:-16}
for c in ${CASES:-A C D M E B}; do
  case $c in
    D)
      for s in 5 25; do
        for i in $(seq 0 $((NIND - 1))); do taskset -c $i timeout 200 $MPIRUN -n 1 --bind-to none $BIN scn/D${i}_${s}.nml > log_D${i}_${s}.txt 2>&1 </dev/null & done; wait
      done
      for i in $(seq 0 $((NIND - 1))); do a=$(tps log_D${i}_5.txt); b=$(tps log_D${i}_25.txt); python3 -c "print(round(($b-$a)/20,3))"; done | awk -v n=$NIND '{s+=$1; if($1>m)m=$1} END {print "D " n " independent 1-rank runs of C_1: mean ms_per_step=" s/NR " max=" m}' >> $RES ;;
    E) [ -n "$E_CKPT" ] && for r in $RANKS; do for b in ${E_BALANCES:-cells points}; do one E_$b $r; done; done ;;
    *) for r in $RANKS; do one $c $r; done ;;
  esac
  tar czf $OUT/logs.tgz log_* probe.log
done
echo "# end $(date -u)" >> $RES; cat $RES
