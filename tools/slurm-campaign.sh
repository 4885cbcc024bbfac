#!/bin/bash
# A 100 000-run Monte Carlo campaign of `tracking` on a Slurm cluster: 100 array tasks of 1 000
# runs each, then one job that merges the slices (docs/campaigns.md). Submit with
#     sbatch tools/slurm-campaign.sh
# Every task runs `acs sim tracking --runs 100000 --seed 1 --range A..B` (a pure function of the
# seed and the run index), so the merged files are byte-identical to the campaign run in one piece.
#SBATCH --job-name=acs-tracking
#SBATCH --array=0-99
#SBATCH --cpus-per-task=2
#SBATCH --time=00:30:00
set -euo pipefail
RUNS=${RUNS:-100000} PER=${PER:-1000} SEED=${SEED:-1} OUT=${OUT:-campaign-tracking}
A=$((SLURM_ARRAY_TASK_ID * PER)); B=$((A + PER))
acs sim tracking --runs "$RUNS" --seed "$SEED" --range "$A..$B" --jobs "${SLURM_CPUS_PER_TASK:-1}" \
  --out "$OUT/slice-$SLURM_ARRAY_TASK_ID"
# the last task to finish is not known here: merge in a job that depends on the whole array, e.g.
#     sbatch --dependency=afterok:$ARRAY_JOB_ID --wrap "acs sim merge $OUT/slice-* --out $OUT/all"
