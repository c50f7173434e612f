# shellcheck shell=bash
# Sourced by the fake Slurm commands in this directory: appends one line,
# "TOOL ARG ...", each argument quoted with printf %q, to $FAKE_SLURM_LOG/calls,
# and writes the caller's environment to $FAKE_SLURM_LOG/TOOL.N.env (N counts
# the calls of TOOL from 1). FAKE_SLURM_LOG must name a directory.
: "${FAKE_SLURM_LOG:?set FAKE_SLURM_LOG to a directory for the fake Slurm commands}"
fake_tool=$(basename "$0")
fake_call=$(($(grep -c "^$fake_tool " "$FAKE_SLURM_LOG/calls" 2>/dev/null || true) + 1))
{
  printf '%s' "$fake_tool"
  printf ' %q' "$@"
  printf '\n'
} >> "$FAKE_SLURM_LOG/calls"
env > "$FAKE_SLURM_LOG/$fake_tool.$fake_call.env"
