# The LDC gain sweep (gain = K·Δt²) of the reproduction, shared by run_report.sh (CPU) and
# gpu_paper.sh (GPU, twice the resolution). Sourced; the caller defines run NAME ARGS...
#
#   k_sweep "$BASE"   # BASE: the scene options (--a, --na, --nz, --length)
k_sweep() {
  local base=$1 g
  for g in 0.03 0.2 0.3 0.5 0.8 1.0; do
    run dam_ldc1_g$g  --scene dam  $base --iterations 1 --ldc 1 --gain $g --frames 90
    run tank_ldc1_g$g --scene tank $base --iterations 1 --ldc 1 --gain $g --frames 60
  done
  for g in 0.03 0.2 0.3 0.5; do
    run dam_ldc2_g$g  --scene dam  $base --iterations 2 --ldc 1 --gain $g --frames 90
    run tank_ldc2_g$g --scene tank $base --iterations 2 --ldc 1 --gain $g --frames 60
  done
}
