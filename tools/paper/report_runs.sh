# The simulations of the LDC reproduction (docs/paper/README.md), shared by run_report.sh (the CPU
# backend, one command) and gpu_report.sh (the same scenes and resolution on the CUDA backend, in
# one device call). Sourced; the caller defines `run NAME ARGS...` (one pbf_paper run into
# NAME.csv) and SNAP (a folder for the particle snapshots of §3).
#
#   report_runs        # §1-§4, §6, §7, §9 and §10 of the report (12,288 particles per scene)
#   cost_runs BASE     # the equal-cost comparison (README "Cost per frame"): cost_*.csv
source "$(dirname "${BASH_SOURCE[0]}")/k_sweep.sh"  # k_sweep BASE

# The methods of the cost comparison: PBF 1..4 iterations, LDC (the default gain 0.3) 1..3.
COST_METHODS="conv1 conv2 conv3 conv4 ldc1 ldc2 ldc3"
# Substeps per 1/60 s frame: the library's automatic rule and fixed counts around it (14 is the
# CFL-like rule of the 64/a scenes).
COST_SUBSTEPS="auto 3 5 7 10 14"

report_runs() {
  # The common scene: a = 0.4 m, 32 particles across a, 6 layers deep; dam tank 5a long.
  # 12,288 particles in both scenes; substeps from the CFL-like rule (7 per 1/60 s frame) for
  # every method, so methods differ only in iterations and LDC.
  local BASE="--a 0.4 --na 32 --nz 6 --length 5"
  local DAM_SNAPS="--snap-times 0.2,0.4,0.6,1.0" TANK_SNAPS="--snap-times 1.0"
  local it S res nz eta scene frames

  # 1. Methods: conventional PBF 1..6 iterations, LDC (gain 0.1, the library's old default, set
  #    explicitly; it is 0.3 now) 1..3 iterations.
  for it in 1 2 3 4 5 6; do
    run dam_conv$it  --scene dam  $BASE --iterations $it --ldc 0 --frames 90 $DAM_SNAPS --snap-prefix "$SNAP/dam_conv$it"
    run tank_conv$it --scene tank $BASE --iterations $it --ldc 0 --frames 60 $TANK_SNAPS --snap-prefix "$SNAP/tank_conv$it"
  done
  for it in 1 2 3; do
    run dam_ldc$it  --scene dam  $BASE --iterations $it --ldc 1 --gain 0.1 --frames 90 $DAM_SNAPS --snap-prefix "$SNAP/dam_ldc$it"
    run tank_ldc$it --scene tank $BASE --iterations $it --ldc 1 --gain 0.1 --frames 60 $TANK_SNAPS --snap-prefix "$SNAP/tank_ldc$it"
  done

  # 2. K sweep (gain = K·Δt²) at 1 and 2 iterations; gain 0 is conventional, 0.1 is above.
  k_sweep "$BASE"

  # 3. Substeps: stability of 1-2 iterations with fewer (and more) substeps than the rule's 7.
  for S in 1 2 4 10 16; do
    run sub_conv1_S$S --scene dam $BASE --iterations 1 --ldc 0 --substeps $S --frames 48
    run sub_ldc1_S$S  --scene dam $BASE --iterations 1 --ldc 1 --gain 0.1 --substeps $S --frames 48
    run sub_conv2_S$S --scene dam $BASE --iterations 2 --ldc 0 --substeps $S --frames 48
  done
  #    LDC at the gain the sweep recommends (0.3), with few substeps.
  for S in 1 2 4; do
    run sub_ldc1g0.3_S$S --scene dam $BASE --iterations 1 --ldc 1 --gain 0.3 --substeps $S --frames 48
  done
  #    Large steps: the dam break at 2 substeps per frame (Δt = 1/120 s), every method, to see
  #    whether the flow attenuation of the paper's Fig. 6 appears when steps are large.
  for it in 1 2 3 4 5 6; do
    run damS2_conv$it --scene dam $BASE --iterations $it --ldc 0 --substeps 2 --frames 90
  done
  for it in 1 2 3; do
    run damS2_ldc$it --scene dam $BASE --iterations $it --ldc 1 --gain 0.1 --substeps 2 --frames 90
  done

  # 4. Martin & Moyce: the front sampled every substep up to T ≈ 3.3, at four resolutions with
  #    the thickness a/3 (nz = na/3), LDC (gain 0.1, the old default, set explicitly) + 4
  #    iterations and conventional; and the CI test's resolution at the library's default now
  #    (gain 0.3), which tests/test_validation.cpp runs.
  for res in "16 5" "24 8" "32 11" "40 13"; do
    set -- $res
    run mm_ldc4_na$1 --scene dam --a 0.4 --na $1 --nz $2 --length 5 --iterations 4 --ldc 1 --gain 0.1 --frames 40 --per-substep 1
    run mm_conv4_na$1 --scene dam --a 0.4 --na $1 --nz $2 --length 5 --iterations 4 --ldc 0 --frames 40 --per-substep 1
  done
  run mm_ldc4g0.3_na24 --scene dam --a 0.4 --na 24 --nz 8 --length 5 --iterations 4 --ldc 1 --gain 0.3 --frames 40 --per-substep 1

  # 5. Diagnostics of the instabilities and of the wall compaction (README §10), one knob at a time.
  local D24="--scene dam --a 0.4 --na 24 --nz 4 --length 5 --iterations 1 --ldc 0 --frames 40"
  run diag_dam_1it_default $D24
  run diag_dam_1it_scorr0  $D24 --scorr-k 0
  run diag_dam_1it_relax3  $D24 --relaxation 3
  run diag_dam_1it_noxsph_novort $D24 --xsph 0 --vorticity 0
  local T32="--scene tank $BASE --iterations 1 --ldc 0 --frames 20"
  run diag_tank_1it_default $T32
  run diag_tank_1it_scorr0  $T32 --scorr-k 0
  run diag_tank_1it_relax3  $T32 --relaxation 3
  run diag_tank_1it_S16     $T32 --substeps 16
  for nz in 4 8 16; do
    run diag_tank_6it_nz$nz --scene tank --a 0.4 --na 16 --nz $nz --iterations 6 --ldc 0 --frames 40
  done

  # 7. Adaptive iterations (README §9): iterate until the mean compressive density error is below
  #    η, with a cap of 30 iterations per substep. PBF (LDC off) and LDC at the recommended gain
  #    0.3 as the warm start, η = 1 %, 0.5 %, 0.1 %, both scenes. Sampled every substep
  #    (--per-substep 1, the same physics) so the CSV holds the iterations of every substep and
  #    its time. Dam 90 frames and tank 60 as in §1.
  for eta in 0.01 0.005 0.001; do
    for scene in dam tank; do
      frames=$([[ $scene == dam ]] && echo 90 || echo 60)
      run adapt_${scene}_conv_eta$eta --scene $scene $BASE --iterations 30 --adaptive-target $eta --ldc 0 \
        --frames $frames --per-substep 1
      run adapt_${scene}_ldc_eta$eta --scene $scene $BASE --iterations 30 --adaptive-target $eta --ldc 1 --gain 0.3 \
        --frames $frames --per-substep 1
    done
  done
}

# The equal-cost comparison: every method of COST_METHODS at every S of COST_SUBSTEPS, dam and
# tank, 2 s (120 frames, the frame benchmark's length and verdict rules, applied by plot.py), one
# pbf_world_step per frame so that the CSV's step_ms is the backend's time of the whole frame.
cost_runs() {
  local base=$1 m S scene
  for scene in dam tank; do
    for m in $COST_METHODS; do
      for S in $COST_SUBSTEPS; do
        case $m in
          conv*) run cost_${scene}_${m}_S$S --scene $scene $base --iterations ${m#conv} --ldc 0 --substeps $S --frames 120 ;;
          ldc*)  run cost_${scene}_${m}_S$S --scene $scene $base --iterations ${m#ldc} --ldc 1 --gain 0.3 --substeps $S --frames 120 ;;
        esac
      done
    done
  done
}
