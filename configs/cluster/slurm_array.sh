#!/usr/bin/env bash
# A prism dataset as a Slurm job array: each array task renders one shard (frames i with
# i mod SLURM_ARRAY_TASK_COUNT == its index), all into one output folder on a shared file system.
# prism reads SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT (and SLURM_ARRAY_TASK_MIN) itself.
# A rerun of the array (or of failed tasks) resumes: finished frames are skipped.
#
#   sbatch configs/cluster/slurm_array.sh configs/datasets/tabletop.ron /shared/out/tabletop
#
#SBATCH --job-name=prism-dataset
#SBATCH --array=0-15
#SBATCH --cpus-per-task=8
#SBATCH --mem=8G
#SBATCH --time=02:00:00
#SBATCH --output=prism-dataset-%A_%a.log
set -euo pipefail
config=${1:?usage: sbatch slurm_array.sh CONFIG OUT}
out=${2:?usage: sbatch slurm_array.sh CONFIG OUT}
prism=${PRISM_BIN:-prism}
exec "$prism" dataset "$config" -o "$out" --threads "${SLURM_CPUS_PER_TASK:-1}"
