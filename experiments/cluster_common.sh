# Sourced by the scripts that launch two MPI ranks on this one machine (cluster_rounds.sh,
# cluster_run_pairs.sh, cluster_sliced_pairs.sh, evaluation_pairs.sh, finalize_wakes.sh): the one
# launch line they share, and the paper config cut to fewer decisions that the whole-run pairs use.
# Two ranks, not bound to a core each (a rank's threads would share one), shared memory between
# them without the single-copy mechanism (it needs ptrace rights containers often withhold), and
# Open MPI's own control traffic on loopback only (docs/cluster.md, "Use"). Root may launch (the CI
# and these VMs run as root).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPI="mpirun -np 2 --bind-to none --oversubscribe --mca btl self,vader --mca btl_vader_single_copy_mechanism none --mca oob_tcp_if_include lo"

# $1: decisions D, $2: the config file to write, $3: the calling script's name (for its message).
# Writes configs/paper.toml (from the repository's root, the caller's working directory) cut to D
# decisions, its phase boundaries (T1, T2, the entropy decay) scaled by D / 1000000 so that a run
# passes through every phase; exits 2 if a key to change is not in the config.
paper_cut_to() {
  local d=$1 cfg=$2 key
  scaled() { awk -v d="$d" -v v="$1" 'BEGIN { printf "%d", v * d / 1000000 }'; }
  sed -E "s/^total_timesteps = [0-9]+/total_timesteps = $d/;
          s/^exploration_end = [0-9]+/exploration_end = $(scaled 220000)/;
          s/^exploitation_start = [0-9]+/exploitation_start = $(scaled 800000)/;
          s/^ent_decay_start = [0-9]+/ent_decay_start = $(scaled 220000)/;
          s/^ent_decay_end = [0-9]+/ent_decay_end = $(scaled 800000)/" configs/paper.toml > "$cfg"
  for key in total_timesteps exploration_end exploitation_start ent_decay_start ent_decay_end; do
    grep -E "^$key = " "$cfg" > /dev/null || { echo "$3: $key not set in $cfg" >&2; exit 2; }
  done
}
