# Sourced by the scripts that launch two MPI ranks on this one machine (cluster_rounds.sh,
# cluster_run_pairs.sh, evaluation_pairs.sh, finalize_wakes.sh): the one launch line they share.
# Two ranks, not bound to a core each (a rank's threads would share one), shared memory between
# them without the single-copy mechanism (it needs ptrace rights containers often withhold), and
# Open MPI's own control traffic on loopback only (docs/cluster.md, "Use"). Root may launch (the CI
# and these VMs run as root).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPI="mpirun -np 2 --bind-to none --oversubscribe --mca btl self,vader --mca btl_vader_single_copy_mechanism none --mca oob_tcp_if_include lo"
