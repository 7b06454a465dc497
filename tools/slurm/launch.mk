# CLUSTER=slurm: read after outputs/NAME/rules.mk (`make run|release CLUSTER=slurm`), it turns every job of
# the plan into one `srun` step. Make still decides what runs and in which order (inputs, parameter stamps,
# stage binaries); SLURM decides where. Outside an allocation each step is a job of its own; inside one
# (sbatch/salloc, see README "Running on a SLURM cluster") the steps share the allocation's CPUs.
#
# Each step is one task with its stage's CPU count. The stages are single-threaded today; a stage that
# learns to use threads (syn-evaluate --threads) gets them with e.g. CPUS_evaluate=4 — keep it equal to the
# stage's thread parameter.
CPUS_ingest ?= 1
CPUS_retarget ?= 1
CPUS_segment ?= 1
CPUS_synergies ?= 1
CPUS_evaluate ?= 1
CPUS_library ?= 1
CPUS_summary ?= 1

# Passed to every srun, e.g. SRUN_FLAGS="--partition=short --account=lab42 --time=30". On clusters that
# schedule memory, give steps a share (--mem-per-cpu=2G): inside an allocation a step otherwise asks for all
# of the job's memory and the steps run one at a time.
SRUN_FLAGS ?=

# --exact: inside an allocation a step gets only the CPUs it asked for, so make -jN runs N steps side by side.
# --quit-on-interrupt: Ctrl-C stops the steps with make (srun otherwise wants a second one within a second).
# The job name (syn-STAGE-TRIAL) is what squeue, sacct and the job completion log show.
syn_launch = srun --nodes=1 --ntasks=1 --cpus-per-task=$(or $(CPUS_$(1)),1) --exact --quit-on-interrupt \
  --job-name=syn-$(1)-$(2) $(SRUN_FLAGS)
