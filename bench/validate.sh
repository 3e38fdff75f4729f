#!/usr/bin/env bash
# The paper's validations, whose figures the README quotes. Each section writes bench_out/NAME/
# (sweep.csv, sweep.md and one directory per run). Usage: bench/validate.sh [SECTION ...]
#   poiseuille     64 x 64, h = 1.525 dx, dt = 1.25e-6 to t = 0.0125 (Section 5.1)
#   couette        Couette flow from rest, rms error at t = 1
#   cavity         lid-driven cavity, Re = 1, 100, 400, 1000 to steady state, against Ghia et al.
#   equilibrium    stretched membrane, fixed and free, to steady state (Section 5.2.1, Fig. 8)
#   fig10          equilibrium convergence: Nx = 40..160, mu = 0.25, 1, fixed and free (Fig. 10)
#   fig10_fixed    the same, fixed membrane only (minutes; the free runs take hours at Nx = 160)
#   fig10_free     the same, free membrane only (hours; FIG10_NX=40,60,80 for a subset)
#   oscillation    oscillating membrane, mu = 1, 0.1, 0.05, 0.025, t in [0, 10] (Figs. 11, 15-17)
#   fig19          area error at t = 1, 2 against Nx = 40..120 (Fig. 19)
#   table3         self-convergence at t = 0.0625, Nx = 32, 64, 128 against Nx = 256 (Table 3)
#   sweep          the Poiseuille sweep of Figs. 4, 7 and Table 1 (bench/poiseuille_sweep)
#   equilibrium_t10  free membrane in equilibrium without the steady-state stop, t = 10 (area, jump)
#   oscillation_pair the main job with each projection x interpolation pair (area at t = 1, 2, 10)
#   capsule        the capsule in shear (build/capsule_shear), Ca = 0.05, 0.1, 0.2
#   kernel_width   Couette (64 x 64, dt = 1e-3, t = 1) and Poiseuille errors against kernel.h_over_dx 0.51-1.2
# Membranes with laws and bending (docs/membrane_validation.md):
#   capsule_bending  capsule with bending in shear: D/Ca at Ca 0.005-0.05 (H = 2, 4), walls (H = 2, 4, 8),
#                    markers and lattice at Ca 0.05, three laws, against D = Ca_b/sqrt(9 + 4 Ca_b^2)
#   capsule_inertia  the capsule's inclination and D in a wide channel (H = 8, Ca = 0.005) against Re
#                    (0.16, 0.016, 0.0016) and the lattice (dx = 0.0625, 0.03125, 0.0156)
#   relaxation       decay of modes 2 and 3 with bending against n((n^2-1)Eb/R^2)/(4 mu R): Nx = 32-512,
#                    walls (L = 4, 8, 16), markers per dx and h*/h at 256^2
#   oscillation_period  the oscillating membrane's period against h* (h* ~ dx, h* fixed), amplitude and
#                    walls, against the linear mode-2 theory (scripts/membrane_theory.py oscillation)
#   rbc              the red-cell-like capsule in a channel (cases/rbc_channel*.toml): shapes, velocity
#   area_laws        area error at t = 10 for every law with and without bending (cases/membrane_laws.toml)
#   stability_bending  bench/stability_map --parts B (explicit and semi-implicit limits with Eb, Es)
#   stiff            a stiff capsule (explicit limit ~100x below the flow's step) at the flow's step to t = 10
#   bending_cost     paired cpu time, a step with bending against a Hookean step (bench/paired.sh)
#   viscosity_contrast  membrane.viscosity_ratio: the indicator, layered Couette and a circular interface
#                  against exact two-fluid flows, the operator's and the step's orders (build/viscosity_contrast),
#                  and the capsule in shear at lambda = 0.2, 1, 5 (Ca = 0.05, 0.1; 64 x 32 and, Ca = 0.1,
#                  128 x 64) to t = 10 (docs/viscosity_contrast.md)
#   vesicle_shear  a vesicle (inextensible + bending, reduced area 0.8, cases/vesicle_shear.toml) in shear:
#                  tank-treading angle and the tank-treading/tumbling transition against lambda (1 to 16) at
#                  128 x 64, wider channels (H = 4, 8), 256 x 128, and the semi-implicit force's time-step error,
#                  against the 2-D fixed-shape models (scripts/vesicle_theory.py; docs/vesicle_shear.md); the
#                  markers' angular velocity against the model on the runs' own shapes and on a near-circle.
#                  About 3 hours on one core.
#   vesicle_published  the same vesicle at reduced area 0.66 against Quaife & Biros's published-group 2-D
#                  curve (tank-treading angle against lambda, unbounded, boundary integral:
#                  cases/reference/quaife_biros_vesicle_inclination_ra066.csv): lambda = 1-5 at H = 2,
#                  1, 3, 4 at H = 4, 3 to 5 at H = 8 (the transition), 3 and 4 at H = 16, and Ca = 10 at lambda = 1
#                  (docs/vesicle_shear.md). About four hours on one core.
# Free surfaces and loads (Afanasiev, Makarchuk & Popov 2011; classic SPH = method wcsph with
# wcsph.integrator = predictor_corrector), at the paper's particle numbers:
#   fs_poiseuille  Table 1: start-up Poiseuille, N = 15^2 ... 60^2, error at t = 0.6
#   fs_inclined    Table 2: the inclined plane, N = 15^2 ... 60^2, error at t = 4
#                  (both with dt at half Coelho's viscous bound 0.125 h^2/nu: the predictor-corrector
#                  blows up between 0.85 and 0.99 of it, Poiseuille 30^2, h = 2.2 dx)
#   fs_droplet     Table 3: the elliptic drop, N = 721 ... 7651 (n = 15 ... 50 rings), a at t = 0.8,
#                  h/dx = 1.5 and 1.3
#   fs_dam_break   Section 7: the dam break to t = 0.6 (1250 and 5000 particles, wcsph.delta = 0 and
#                  0.1): front, loads, pictures
#   fs_still       the still tank: hydrostatic loads and spurious speeds, with and without A's p = 0 and
#                  delta-SPH (wcsph.delta)
#   fs_delta       Tables 1-3 by WCSPH with delta-SPH (wcsph.delta = 0.1), against fs_poiseuille ... above
#   fs_lobovsky    Lobovsky et al. (2014)'s dam break (H = 0.3 m) by WCSPH: the pressure probes on the far
#                  wall at 5000 and 20000 particles (docs/free_surfaces.md)
# ISPH (method isph, the paper's second method), the same cases:
#   isph_poiseuille  Table 1's ISPH column: N = 15^2 ... 60^2 (ISPH_NX=15,20,25,30 for a subset), t = 0.6
#   isph_inclined    Table 2's ISPH column: the inclined plane, N = 15^2 ... 60^2 (ISPH_NX for a subset), t = 4
#   isph_droplet     Table 3's ISPH column: the elliptic drop, N = 721 ... 7651, a at t = 0.8, h/dx = 1.5
#   isph_dam_break   Section 7 (1250 and 5000 particles; shifting fickian, xu, none): front, loads
#                    against fs_dam_break's (Fig. 10), pictures
#   isph_still       the still tank of fs_still by ISPH (cases/still_tank_isph.toml): loads, spurious
#                    speeds, isph.scheme = consistent and paper
#   isph_lobovsky    Lobovsky et al. (2014)'s dam break by ISPH: the pressure probes at 5000 and 20000 particles
#                    (a 1 ms window; scripts/probe_windows.py: the single-step, 1 ms and 5 ms peaks)
#   isph_gate        the dam break by ISPH behind a gate lifted at sqrt(g H / 2) (gate.*; docs/free_surfaces.md):
#                    the front at 1250 and 5000 particles, and the delay that fits the experiments best
#   isph_lobovsky_gate  Lobovsky et al.'s dam break by ISPH behind the same gate law: the probes at 5000 and
#                    20000 particles (LOBOVSKY_NX=268 for 5000 alone)
#   fs_gate          the dam break by WCSPH behind the same gate: the front at 1250 and 5000 particles
#   fs_lobovsky_gate Lobovsky et al.'s dam break by WCSPH (delta-SPH) behind the same gate: the probes at 5000
#                    and 20000 particles (LOBOVSKY_NX=268 for 5000 alone)
#   isph_scheme      Tables 1-3 with isph.scheme = paper (the scheme before issue 29), for the comparison
# Without arguments: all but fig10 and sweep (the long ones).
# PAIR=paper runs every scene with the paper's approximate projection and SPH interpolation
# (fluid.projection = "approximate", coupling.interpolation = "sph") into bench_out/paper/; the
# default is the conservative pair (exact projection, divergence-free markers).
set -euo pipefail
cd "$(dirname "$0")/.."
SPHIB=build/sphib
SWEEP="/usr/bin/python3 scripts/sweep.py"
OUT=bench_out
PAIR_SETS=()
if [ "${PAIR:-}" = paper ]; then
  OUT=bench_out/paper
  PAIR_SETS=(--set fluid.projection=approximate --set coupling.interpolation=sph)
  SWEEP="$SWEEP ${PAIR_SETS[*]}"
fi
sections=("$@")
[ ${#sections[@]} -gt 0 ] || sections=(poiseuille couette cavity equilibrium oscillation fig19 table3)
cmake --build build --target sphib poiseuille_sweep capsule_shear membrane_relaxation stability_map viscosity_contrast > /dev/null

for s in "${sections[@]}"; do
  case "$s" in
    poiseuille)
      $SWEEP --scene cases/poiseuille.toml --out $OUT/poiseuille --vary grid.nx=64 \
        --report rms_error,seconds_per_step,setup_seconds ;;
    kernel_width)
      $SWEEP --scene cases/couette.toml --out $OUT/kernel_width_couette --vary kernel.h_over_dx=0.51,0.6,0.7,0.8,0.9,1.0,1.2 \
        --set grid.nx=64 --set grid.ny=64 --set time.dt=1e-3 --report rms_error
      $SWEEP --scene cases/poiseuille.toml --out $OUT/kernel_width_poiseuille --vary kernel.h_over_dx=0.51,0.6,0.7,0.8,0.9,1.0,1.2 \
        --report rms_error ;;
    couette)
      $SWEEP --scene cases/couette.toml --out $OUT/couette --vary grid.nx=16,32,64 --derive grid.ny={grid.nx} \
        --report rms_error,seconds_per_step ;;
    cavity)
      for re in 1 100 400 1000; do
        $SWEEP --scene cases/cavity_re$re.toml --out $OUT/cavity_re$re --vary grid.nx=64 \
          --report reynolds,stop_reason,time,max_deviation,rms_deviation,max_deviation_u,max_deviation_v,max_div_u
      done ;;
    equilibrium)
      $SWEEP --scene cases/membrane_equilibrium.toml --out $OUT/equilibrium --vary membrane.fixed=true,false \
        --report stop_reason,time,pressure_jump,pressure_jump_exact,pressure_mad_error,velocity_mad_error,area_relative_error,max_speed ;;
    fig10)
      $SWEEP --scene cases/membrane_equilibrium.toml --out $OUT/fig10 \
        --vary grid.nx=40,60,80,100,120,140,160 --vary fluid.mu=0.25,1 --vary membrane.fixed=true,false \
        --derive grid.ny={grid.nx} --derive time.dt=0.1*3/{grid.nx} \
        --set kernel.h_over_dx=2.25 --set membrane.h_star_over_h=0.5 --set membrane.nb=360 --set output.interval=0 \
        --report pressure_mad_error,velocity_mad_error,pressure_jump,area_relative_error,time ;;
    fig10_fixed)
      $SWEEP --scene cases/membrane_equilibrium.toml --out $OUT/fig10_fixed \
        --vary grid.nx=40,60,80,100,120,140,160 --vary fluid.mu=0.25,1 \
        --derive grid.ny={grid.nx} --derive time.dt=0.1*3/{grid.nx} \
        --set kernel.h_over_dx=2.25 --set membrane.h_star_over_h=0.5 --set membrane.nb=360 --set output.interval=0 \
        --set membrane.fixed=true --report pressure_mad_error,velocity_mad_error,pressure_jump,time ;;
    fig10_free)
      $SWEEP --scene cases/membrane_equilibrium.toml --out $OUT/fig10_free \
        --vary grid.nx=${FIG10_NX:-40,60,80,100,120,140,160} --vary fluid.mu=0.25,1 \
        --derive grid.ny={grid.nx} --derive time.dt=0.1*3/{grid.nx} \
        --set kernel.h_over_dx=2.25 --set membrane.h_star_over_h=0.5 --set membrane.nb=360 --set output.interval=0 \
        --set membrane.fixed=false \
        --report pressure_mad_error,velocity_mad_error,pressure_jump,area_relative_error,stop_reason,time ;;
    oscillation)
      $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation --vary fluid.mu=1,0.1,0.05,0.025 \
        --report period,amplitude_decay,rx_first_minimum,area_relative_error_at.1,area_relative_error_at.2,area_relative_error_at.10,seconds_per_step ;;
    fig19)
      $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/fig19 --vary grid.nx=40,60,80,100,120 \
        --derive grid.ny={grid.nx} --derive time.dt=0.1*3/{grid.nx} \
        --set membrane.T0=1 --set fluid.mu=0.05 --set membrane.nb=360 --set membrane.h_star=0.0425 \
        --set time.end=2 --set output.interval=0 \
        --report area_relative_error_at.1,area_relative_error_at.2 ;;
    table3)
      /usr/bin/python3 scripts/self_convergence.py --out $OUT/table3 "${PAIR_SETS[@]}" ;;
    sweep)
      build/poiseuille_sweep --out $OUT/poiseuille_sweep ;;
    equilibrium_t10)
      $SWEEP --scene cases/membrane_equilibrium.toml --out $OUT/equilibrium_t10 --vary grid.nx=70 \
        --set time.steady_eps=0 --set time.end=10 \
        --report pressure_jump,pressure_mad_error,velocity_mad_error,area_relative_error_at.1,area_relative_error_at.5,area_relative_error_at.10,max_speed ;;
    oscillation_pair)
      /usr/bin/python3 scripts/sweep.py --scene cases/membrane_oscillation.toml --out $OUT/oscillation_pair \
        --vary fluid.projection=exact,approximate --vary coupling.interpolation=divergence_free,sph \
        --report period,amplitude_decay,rx_first_minimum,t_first_minimum,area_relative_error_at.1,area_relative_error_at.2,area_relative_error_at.10,seconds_per_step ;;
    capsule)
      if [ "${PAIR:-}" = paper ]; then build/capsule_shear --out $OUT/capsule_shear --paper-pair
      else build/capsule_shear --out $OUT/capsule_shear; fi ;;
    fs_poiseuille)
      $SWEEP --scene cases/poiseuille_afanasiev_wcsph.toml --out $OUT/fs_poiseuille --vary grid.nx=15,20,25,30,40,50,60 \
        --derive grid.ny={grid.nx} --derive time.dt=0.3/{grid.nx}**2 --set output.interval=0 \
        --report particles,profile_error,profile_error_max,rms_error,max_density_variation,seconds_per_step ;;
    fs_inclined)
      $SWEEP --scene cases/inclined_plane_wcsph.toml --out $OUT/fs_inclined --vary grid.nx=15,20,25,30,40,50,60 \
        --derive grid.ny=2*{grid.nx} --derive time.dt=0.25/{grid.nx}**2 --set output.interval=0 \
        --report particles,profile_error,profile_error_max,rms_error,max_density_variation,seconds_per_step
      /usr/bin/python3 scripts/plot.py $OUT/fs_inclined/run_005 ;;  # N = 2500: the velocity profile
    fs_droplet)
      $SWEEP --scene cases/droplet_wcsph.toml --out $OUT/fs_droplet --vary grid.nx=93,123,183,243,303 \
        --vary kernel.h_over_dx=1.5,1.3 --derive grid.ny={grid.nx} --derive time.dt=0.0915/{grid.nx} \
        --set time.end=0.8 --set output.times=[] \
        --report particles,droplet_axis_error,droplet_axis_error_extent,max_density_variation,seconds_per_step
      [ -f $OUT/fs_droplet/case/summary.json ] || $SPHIB run cases/droplet_wcsph.toml --out $OUT/fs_droplet/case --quiet
      /usr/bin/python3 scripts/plot.py $OUT/fs_droplet/case ;;
    fs_dam_break)
      $SWEEP --scene cases/dam_break_wcsph.toml --out $OUT/fs_dam_break --vary grid.nx=200,100 --vary wcsph.delta=0,0.1 \
        --derive grid.ny=2*{grid.nx} --derive time.dt=0.008/{grid.nx} \
        --report particles,front_deviation_koshizuka_oka_1996,front_deviation_martin_moyce_1952_a1_125in,front_deviation_martin_moyce_1952_a2_25in,load_left_min,load_right_max,load_right_max_t,max_density_variation,seconds_per_step
      /usr/bin/python3 scripts/plot.py $OUT/fs_dam_break/run_000 ;;
    fs_still)
      $SWEEP --scene cases/still_tank_wcsph.toml --out $OUT/fs_still \
        --vary free_surface.detection=none,dilts --vary wcsph.alpha=0.1,0.3 --vary wcsph.delta=0,0.1 \
        --report force_left,force_bottom,load_left_min,load_left_max,max_speed,max_density_variation ;;
    fs_delta)
      $SWEEP --scene cases/poiseuille_afanasiev_wcsph.toml --out $OUT/fs_delta_poiseuille --vary grid.nx=15,20,25,30,40,50,60 \
        --derive grid.ny={grid.nx} --derive time.dt=0.3/{grid.nx}**2 --set output.interval=0 --set wcsph.delta=0.1 \
        --report particles,profile_error,profile_error_max,rms_error,max_density_variation,seconds_per_step
      $SWEEP --scene cases/inclined_plane_wcsph.toml --out $OUT/fs_delta_inclined --vary grid.nx=15,20,25,30,40,50,60 \
        --derive grid.ny=2*{grid.nx} --derive time.dt=0.25/{grid.nx}**2 --set output.interval=0 --set wcsph.delta=0.1 \
        --report particles,profile_error,profile_error_max,rms_error,max_density_variation,seconds_per_step
      $SWEEP --scene cases/droplet_wcsph.toml --out $OUT/fs_delta_droplet --vary grid.nx=93,123,183,243,303 \
        --vary kernel.h_over_dx=1.5,1.3 --derive grid.ny={grid.nx} --derive time.dt=0.0915/{grid.nx} \
        --set time.end=0.8 --set output.times=[] --set wcsph.delta=0.1 \
        --report particles,droplet_axis_error,droplet_axis_error_extent,max_density_variation,seconds_per_step ;;
    fs_lobovsky)
      $SWEEP --scene cases/dam_break_lobovsky_wcsph.toml --out $OUT/fs_lobovsky --vary grid.nx=268,536 \
        --derive grid.ny={grid.nx}*75//134 --derive time.dt=0.01474/{grid.nx} --set output.interval=0 --set output.diagnostics_every=1 \
        --report particles,probe_P1_max,probe_P1_max_t,probe_P2_max,probe_P2_max_t,probe_P3_max,probe_P3_max_t,probe_P4_max,probe_P4_max_t,load_right_max,load_right_max_t,max_density_variation,seconds_per_step
      /usr/bin/python3 scripts/plot_probes.py $OUT/fs_lobovsky/probes.png $OUT/fs_lobovsky/run_000 $OUT/fs_lobovsky/run_001 ;;
    isph_poiseuille|isph_inclined|isph_droplet|isph_scheme)
      [ "$s" = isph_scheme ] && schemes=(paper) || schemes=(consistent)
      [ "$s" = isph_scheme ] && tag=_paper || tag=
      if [ "$s" = isph_poiseuille ] || [ "$s" = isph_scheme ]; then
        $SWEEP --scene cases/poiseuille_afanasiev_isph.toml --out $OUT/isph_poiseuille$tag --vary grid.nx=${ISPH_NX:-15,20,25,30,40,50,60} \
          --derive grid.ny={grid.nx} --set output.interval=0 --set isph.scheme=${schemes[0]} \
          --report particles,profile_error,profile_error_max,rms_error,poisson_cg_iterations,seconds_per_step
      fi
      if [ "$s" = isph_inclined ] || [ "$s" = isph_scheme ]; then
        $SWEEP --scene cases/inclined_plane.toml --out $OUT/isph_inclined$tag --vary grid.nx=${ISPH_NX:-15,20,25,30,40,50,60} \
          --derive grid.ny=2*{grid.nx} --set output.interval=0 --set isph.scheme=${schemes[0]} \
          --report particles,profile_error,profile_error_max,rms_error,seconds_per_step
      fi
      if [ "$s" = isph_droplet ] || [ "$s" = isph_scheme ]; then
        $SWEEP --scene cases/droplet.toml --out $OUT/isph_droplet$tag --vary grid.nx=93,123,183,243,303 \
          --derive grid.ny={grid.nx} --derive time.dt=0.0915/{grid.nx} --set time.end=0.8 --set output.times=[] \
          --set isph.scheme=${schemes[0]} --report particles,droplet_axis_error,droplet_axis_error_extent,seconds_per_step
        if [ "$s" = isph_droplet ]; then
          [ -f $OUT/isph_droplet/case/summary.json ] || $SPHIB run cases/droplet.toml --out $OUT/isph_droplet/case --quiet
          /usr/bin/python3 scripts/plot.py $OUT/isph_droplet/case
        fi
      fi ;;
    isph_dam_break)
      $SWEEP --scene cases/dam_break.toml --out $OUT/isph_dam_break --vary grid.nx=200,100 --vary isph.shifting=fickian,xu,none \
        --derive grid.ny=4*{grid.nx} --derive time.dt=0.03/{grid.nx} \
        --report particles,front_deviation_koshizuka_oka_1996,front_deviation_martin_moyce_1952_a1_125in,front_deviation_martin_moyce_1952_a2_25in,load_left_min,load_right_max,load_right_max_t,poisson_cg_iterations,seconds_per_step
      compare=()
      [ -f $OUT/fs_dam_break/run_000/diagnostics.csv ] && compare=(--compare $OUT/fs_dam_break/run_000)
      /usr/bin/python3 scripts/plot.py $OUT/isph_dam_break/run_000 "${compare[@]}" ;;
    isph_still)
      $SWEEP --scene cases/still_tank_isph.toml --out $OUT/isph_still --vary grid.nx=40 --vary isph.scheme=consistent,paper \
        --report force_left,force_bottom,load_left_min,load_left_max,max_speed ;;
    isph_lobovsky)
      # a 1 ms window: probe_windows.py gives the single-step, 1 ms and 5 ms peaks from it
      $SWEEP --scene cases/dam_break_lobovsky.toml --out $OUT/isph_lobovsky --vary grid.nx=268,536 \
        --derive grid.ny={grid.nx}*75//134 --derive time.dt=0.067/{grid.nx} --set output.interval=0 --set output.diagnostics_every=1 \
        --set observe.probe_window=1.0e-3 \
        --report particles,probe_P1_max,probe_P1_max_t,probe_P2_max,probe_P2_max_t,probe_P3_max,probe_P3_max_t,probe_P4_max,probe_P4_max_t,load_right_max,load_right_max_t,poisson_cg_iterations,seconds_per_step
      /usr/bin/python3 scripts/probe_windows.py $OUT/isph_lobovsky/run_000 | tee $OUT/isph_lobovsky/windows.txt
      /usr/bin/python3 scripts/probe_windows.py $OUT/isph_lobovsky/run_001 | tee -a $OUT/isph_lobovsky/windows.txt
      /usr/bin/python3 scripts/plot_probes.py $OUT/isph_lobovsky/probes.png $OUT/isph_lobovsky/run_000 $OUT/isph_lobovsky/run_001 ;;
    isph_gate)  # the gate lifted at sqrt(g H / 2) = 1.197 m/s for H = 2a = 0.292 m, from t = 0
      $SWEEP --scene cases/dam_break.toml --out $OUT/isph_gate --vary grid.nx=200,100 \
        --derive grid.ny=4*{grid.nx} --derive time.dt=0.03/{grid.nx} --set gate.x=0.146 --set gate.speed=1.197 \
        --set time.end=0.3 --set output.times=[] \
        --report particles,front_deviation_koshizuka_oka_1996,front_deviation_martin_moyce_1952_a1_125in,front_deviation_martin_moyce_1952_a2_25in,seconds_per_step
      /usr/bin/python3 scripts/dam_break_front.py $OUT/isph_gate/run_000 $OUT/isph_gate/run_001 | tee $OUT/isph_gate/front.txt ;;
    isph_lobovsky_gate)  # the gate lifted at sqrt(g H / 2) = 1.213 m/s for H = 0.3 m, from t = 0 (their time origin); its face on the lattice line 100 dx next to the column
      $SWEEP --scene cases/dam_break_lobovsky.toml --out $OUT/isph_lobovsky_gate --vary grid.nx=${LOBOVSKY_NX:-268,536} \
        --derive grid.ny={grid.nx}*75//134 --derive time.dt=0.067/{grid.nx} --set output.interval=0 --set output.diagnostics_every=1 \
        --set gate.x=0.600746 --set gate.speed=1.213 --set time.end=0.55 \
        --report particles,probe_P1_max,probe_P1_max_t,probe_P2_max,probe_P2_max_t,probe_P3_max,probe_P3_max_t,probe_P4_max,probe_P4_max_t,seconds_per_step ;;
    fs_gate)  # as isph_gate
      $SWEEP --scene cases/dam_break_wcsph.toml --out $OUT/fs_gate --vary grid.nx=200,100 \
        --derive grid.ny=2*{grid.nx} --derive time.dt=0.008/{grid.nx} --set gate.x=0.146 --set gate.speed=1.197 \
        --set time.end=0.3 --set output.times=[] \
        --report particles,front_deviation_koshizuka_oka_1996,front_deviation_martin_moyce_1952_a1_125in,front_deviation_martin_moyce_1952_a2_25in,max_density_variation,seconds_per_step
      /usr/bin/python3 scripts/dam_break_front.py $OUT/fs_gate/run_000 $OUT/fs_gate/run_001 | tee $OUT/fs_gate/front.txt ;;
    fs_lobovsky_gate)  # as isph_lobovsky_gate
      $SWEEP --scene cases/dam_break_lobovsky_wcsph.toml --out $OUT/fs_lobovsky_gate --vary grid.nx=${LOBOVSKY_NX:-268,536} \
        --derive grid.ny={grid.nx}*75//134 --derive time.dt=0.01474/{grid.nx} --set output.interval=0 --set output.diagnostics_every=1 \
        --set gate.x=0.600746 --set gate.speed=1.213 --set time.end=0.55 \
        --report particles,probe_P1_max,probe_P1_max_t,probe_P2_max,probe_P2_max_t,probe_P3_max,probe_P3_max_t,probe_P4_max,probe_P4_max_t,max_density_variation,seconds_per_step ;;
    capsule_bending)  # (one thread per run: the two cores are shared)
      C="env OMP_NUM_THREADS=1 build/capsule_shear --sheared --law skalak --eb-hat 0.1 --t-end 6"
      $C --ca 0.005,0.01,0.02,0.05 --cfl 0.05 --out $OUT/capsule_bending/ca_H2
      $C --ca 0.005,0.01,0.02,0.05 --cfl 0.025 --out $OUT/capsule_bending/ca_H2_dt2
      $C --ca 0.005,0.01,0.02,0.05 --cfl 0.0125 --explicit --out $OUT/capsule_bending/ca_H2_explicit
      $C --ca 0.005,0.01,0.02,0.05 --cfl 0.1 --height 4 --nx 128 --out $OUT/capsule_bending/ca_H4
      $C --ca 0.01 --cfl 0.2 --height 8 --nx 256 --out $OUT/capsule_bending/ca_H8
      for nb in 80 128 256; do $C --ca 0.05 --nx 64 --nb $nb --cfl 0.025 --out $OUT/capsule_bending/res_nx64_nb$nb; done
      for nb in 128 160 256; do $C --ca 0.05 --nx 128 --nb $nb --cfl 0.05 --out $OUT/capsule_bending/res_nx128_nb$nb; done
      $C --ca 0.05 --nx 256 --nb 320 --cfl 0.1 --out $OUT/capsule_bending/res_nx256_nb320
      for law in hookean neo_hookean; do
        env OMP_NUM_THREADS=1 build/capsule_shear --sheared --law $law --eb-hat 0.1 --t-end 6 --ca 0.01 --cfl 0.05 \
          --out $OUT/capsule_bending/law_$law
      done ;;
    capsule_inertia)  # (one thread per run: the two cores are shared)
      C="env OMP_NUM_THREADS=1 build/capsule_shear --sheared --law skalak --eb-hat 0.1 --t-end 6 --ca 0.005 --cfl 0.2 --height 8"
      for nx in 256 512 1024; do
        for rho in 1 0.1 0.01; do $C --nx $nx --rho $rho --out $OUT/capsule_inertia/nx${nx}_rho$rho; done
      done ;;
    relaxation)
      R="env OMP_NUM_THREADS=1 build/membrane_relaxation"
      $R --mode 2,3 --nx 32,64,128,256 --out $OUT/relaxation/L4
      $R --mode 3 --nx 512 --out $OUT/relaxation/L4_512
      $R --mode 2 --nx 128 --length 8 --out $OUT/relaxation/L8
      $R --mode 2 --nx 256 --length 16 --out $OUT/relaxation/L16
      for m in 1 1.5 3; do $R --mode 3 --nx 256 --markers-per-dx $m --out $OUT/relaxation/m$m; done
      $R --mode 3 --nx 256 --h-star-over-h 2 --out $OUT/relaxation/hs2
      $R --mode 3 --nx 128,256 --interpolation divergence_free --out $OUT/relaxation/df || true ;;  # 512: unstable
    oscillation_period)
      P="--set time.end=3.3 --set output.interval=0 --set output.diagnostics_every=10"
      SMALL="--set membrane.rx=0.63 --set membrane.ry=0.5952380952"
      REP=period,amplitude_decay,extrema,rx_first_minimum,t_first_minimum,area_relative_error,seconds_per_step
      N1="env OMP_NUM_THREADS=1"
      $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/hs_dx --vary grid.nx=64,128,256 \
        --derive grid.ny={grid.nx} --derive membrane.nb=2*{grid.nx} $P --report $REP
      $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/hs_fixed --vary grid.nx=128,256 \
        --derive grid.ny={grid.nx} --derive membrane.nb=2*{grid.nx} --set membrane.h_star=0.07875 $P --report $REP
      $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/hs_half --vary grid.nx=256 \
        --derive grid.ny={grid.nx} --derive membrane.nb=2*{grid.nx} --set membrane.h_star=0.039375 $P --report $REP
      $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/small --vary grid.nx=64,128,256 \
        --derive grid.ny={grid.nx} --derive membrane.nb=2*{grid.nx} $SMALL $P --report $REP
      for a in "" "$SMALL"; do
        tag=domain6; [ -n "$a" ] && tag=domain6_small
        $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/$tag --vary grid.nx=128 \
          --derive grid.ny={grid.nx} --set membrane.nb=128 --set membrane.h_star=0.07875 --set domain.x=[-3,3] \
          --set domain.y=[-3,3] $a $P --report $REP
      done
      $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/domain12_small --vary grid.nx=256 \
        --derive grid.ny={grid.nx} --set membrane.nb=128 --set membrane.h_star=0.07875 --set domain.x=[-6,6] \
        --set domain.y=[-6,6] $SMALL $P --report $REP
      $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/domain6_small_conv \
        --vary grid.nx=256,512 --derive grid.ny={grid.nx} --derive membrane.nb={grid.nx} --set domain.x=[-3,3] \
        --set domain.y=[-3,3] $SMALL $P --report $REP
      # the period and decay rate fitted to the whole signal (docs/membrane_validation.md)
      /usr/bin/python3 scripts/oscillation_fit.py $OUT/oscillation_period/small/run_* \
        $OUT/oscillation_period/domain6_small/run_* $OUT/oscillation_period/domain6_small_conv/run_*
      # the kernel widths at a fixed lattice (64^2), and the 64^2 widths on a 128^2 lattice
      $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/h_over_dx_64 \
        --vary kernel.h_over_dx=1.2,1.5,2.0 $P --report $REP
      $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/h_over_dx_64_hs_fixed \
        --vary kernel.h_over_dx=1.2,1.5,2.0 --set membrane.h_star=0.07875 $P --report $REP
      $N1 $SWEEP --scene cases/membrane_oscillation.toml --out $OUT/oscillation_period/widths_of_64_at_128 \
        --vary kernel.h_over_dx=2.4 --set grid.nx=128 --set grid.ny=128 --set membrane.nb=256 \
        --set membrane.h_star=0.07875 $P --report $REP
      /usr/bin/python3 scripts/lattice_kernel_factor.py 1.2 1.5 2.0 2.4
      /usr/bin/python3 scripts/membrane_theory.py oscillation
      /usr/bin/python3 scripts/membrane_theory.py oscillation --rx 0.63 --ry 0.5952380952 ;;
    rbc)
      for c in rbc_channel rbc_channel_offset; do
        [ -f $OUT/rbc/$c/summary.json ] || env OMP_NUM_THREADS=1 $SPHIB run cases/$c.toml --out $OUT/rbc/$c --quiet
      done
      /usr/bin/python3 scripts/plot_membrane_validation.py rbc $OUT/rbc/rbc_channel $OUT/rbc/rbc_channel_offset ;;
    area_laws)
      REP=area_relative_error_at.1,area_relative_error_at.10,period,stretch_error,bending_energy,seconds_per_step
      L="env OMP_NUM_THREADS=1 $SWEEP --scene cases/membrane_laws.toml --set output.interval=0 --report $REP"
      $L --out $OUT/area_laws/hookean --vary membrane.Eb=0,0.01
      $L --out $OUT/area_laws/neo_hookean --vary membrane.Eb=0,0.01 --set membrane.law=neo_hookean --set membrane.Es=2.5
      $L --out $OUT/area_laws/neo_hookean_bspline --vary membrane.Eb=0 --set membrane.law=neo_hookean \
        --set membrane.Es=2.5 --set coupling.interpolation=bspline
      $L --out $OUT/area_laws/skalak --vary membrane.Eb=0,0.01 --set membrane.law=skalak --set membrane.Es=2.5
      # the inextensible vesicle: rest length = the ellipse's perimeter (2 pi r0 = 3.96636)
      I="--set membrane.law=inextensible --set membrane.Es=1000 --set membrane.r0=0.6312658"
      $L --out $OUT/area_laws/inextensible --vary membrane.Eb=0,0.01 $I
      $L --out $OUT/area_laws/inextensible_bspline --vary membrane.nb=96,128 --set coupling.interpolation=bspline $I
      $L --out $OUT/area_laws/inextensible_bending_nb96 --vary membrane.nb=96 --set membrane.Eb=0.01 $I
      # without the tension's cutoff (its default is 2 dx), and started at its rest spacing
      $L --out $OUT/area_laws/inextensible_no_cutoff --vary membrane.Eb=0,0.01 --set membrane.tension_cutoff=0 $I
      $L --out $OUT/area_laws/inextensible_arclength --vary membrane.Eb=0,0.01 --set membrane.spacing=arclength $I ;;
    stability_bending)
      build/stability_map --parts B --out $OUT/stability_bending ;;
    stiff)  # Eb = 24 Es r0^2 = 30.7: explicit stable at dt = 7.8e-5, not at 1.6e-4; the flow's step 0.0156 (CFL 0.25)
      S="env OMP_NUM_THREADS=1 build/capsule_shear --sheared --law skalak --eb-hat 24 --ca 0.05 --t-end 10"
      for nb in 40 60 80; do $S --nb $nb --cfl 0.25 --out $OUT/stiff/semi_nb${nb}_cfl0.25; done
      for nb in 40 60; do $S --nb $nb --cfl 0.1 --out $OUT/stiff/semi_nb${nb}_cfl0.1; done
      $S --nb 60 --cfl 0.00125 --explicit --out $OUT/stiff/explicit_nb60_cfl0.00125
      $S --nb 80 --cfl 0.00125 --explicit --out $OUT/stiff/explicit_nb80_cfl0.00125
      for c in 0.0025 0.005; do $S --nb 60 --cfl $c --explicit --t-end 1 --out $OUT/stiff/explicit_nb60_cfl$c || true; done ;;
    bending_cost)
      A="env OMP_NUM_THREADS=1 build/sphib run cases/membrane_oscillation.toml --quiet --set time.end=2"
      bash bench/paired.sh -n 6 -- "$A --out $OUT/bending_cost/a" "$A --out $OUT/bending_cost/b --set membrane.Eb=0.001" ;;
    viscosity_contrast)
      mkdir -p $OUT/viscosity_contrast
      build/viscosity_contrast | tee $OUT/viscosity_contrast/numerics.txt
      for l in 0.2 1 5; do
        build/capsule_shear --ca 0.05,0.1 --lambda $l --t-end 10 --out $OUT/viscosity_contrast/capsule_64_lambda_$l
        build/capsule_shear --ca 0.1 --lambda $l --t-end 10 --nx 128 --out $OUT/viscosity_contrast/capsule_128_lambda_$l
      done ;;
    vesicle_shear)  # (one thread per run: the two cores are shared)
      V="env OMP_NUM_THREADS=1 build/sphib run cases/vesicle_shear.toml --quiet"  # 128 x 64, explicit force, dt = 1e-3
      H4=(--set grid.nx=256 --set grid.ny=128 --set 'domain.x=[-4.0, 4.0]' --set 'domain.y=[-2.0, 2.0]'
          --set 'walls.bottom=[-2.0, 0.0]' --set 'walls.top=[2.0, 0.0]')  # H = 4 (confinement 0.2), same dx
      N256="--set grid.nx=256 --set grid.ny=128 --set membrane.nb=256"
      D=$OUT/vesicle_shear
      mkdir -p $D/semi_implicit $D/checks
      /usr/bin/python3 scripts/vesicle_theory.py check | tee $D/theory.txt
      /usr/bin/python3 scripts/vesicle_theory.py angle --nu 0.8 --lam 1,2,3,4,5,6,8,12,16 | tee -a $D/theory.txt
      for l in 1 2 3 4 5 6 8 12 16; do $V --set membrane.viscosity_ratio=$l --out $D/n128_l$l; done  # 1-6 min each
      $V --set membrane.viscosity_ratio=16 --set time.end=40 --out $D/n128_l16_t40
      for l in 1 3; do $V --set membrane.viscosity_ratio=$l "${H4[@]}" --out $D/H4_n128_l$l; done  # 2 and 10 min
      # the markers' angular velocity (docs/vesicle_shear.md, "checks"): the walls (H = 8: 512 x 256), the
      # model on the runs' own shapes, the near-circle against the ellipse model of its reduced area
      H8=(--set grid.nx=512 --set grid.ny=256 --set 'domain.x=[-8.0, 8.0]' --set 'domain.y=[-4.0, 4.0]'
          --set 'walls.bottom=[-4.0, 0.0]' --set 'walls.top=[4.0, 0.0]')
      $V "${H8[@]}" --set output.interval=1 --set time.end=16 --out $D/H8_n128_l1   # 2 min
      $V "${H8[@]}" --set membrane.viscosity_ratio=3 --set time.end=14 --out $D/H8_n128_l3   # 15 min
      C=(--set membrane.shape=circle --set membrane.radius=0.4 --set time.end=3)
      $V "${C[@]}" --out $D/checks/c_H2; $V "${C[@]}" "${H4[@]}" --out $D/checks/c_H4; $V "${C[@]}" "${H8[@]}" --out $D/checks/c_H8
      $V "${C[@]}" --set grid.nx=64 --set grid.ny=32 --set membrane.nb=64 --out $D/checks/c_n64
      $V "${C[@]}" $N256 --set time.dt=5e-4 --out $D/checks/c_n256
      /usr/bin/python3 scripts/vesicle_shear.py $D/checks/* | tee $D/checks.txt
      /usr/bin/python3 scripts/vesicle_theory.py shape $D/n128_l1 $D/H4_n128_l1 $D/H8_n128_l1 --lam 1 | tee -a $D/checks.txt
      /usr/bin/python3 scripts/vesicle_theory.py shape $D/n128_l3 $D/H4_n128_l3 $D/H8_n128_l3 --lam 3 | tee -a $D/checks.txt
      $V --set membrane.viscosity_ratio=3 --set membrane.Eb=0.64 --set time.dt=5e-4 --set time.end=15 --out $D/ca0.1_n128_l3
      for l in 1 3; do $V --set membrane.viscosity_ratio=$l $N256 --set time.dt=2.5e-4 --set time.end=10 --out $D/n256_l$l; done
      # the semi-implicit force (membrane.semi_implicit = true): its time-step error, and the lattices
      S="$V --set membrane.semi_implicit=true"
      for dt in 5e-4 2.5e-4; do $S --set time.dt=$dt --set time.end=10 --out $D/semi_implicit/n128_l1_dt$dt; done  # dt = 1e-3: n128_l1
      $V --set time.dt=5e-4 --set time.end=10 --out $D/semi_implicit/explicit_n128_l1_dt5e-4
      for l in 1 2 3 4 5; do
        $S --set membrane.viscosity_ratio=$l --set grid.nx=64 --set grid.ny=32 --set membrane.nb=64 --set time.dt=2e-3 \
          --set time.end=30 --out $D/semi_implicit/n64_l$l
        $S --set membrane.viscosity_ratio=$l --set time.end=30 --out $D/semi_implicit/n128_l$l
      done
      for l in 1 3; do $S --set membrane.viscosity_ratio=$l $N256 --set time.dt=5e-4 --set time.end=30 --out $D/semi_implicit/n256_l$l; done
      /usr/bin/python3 scripts/vesicle_shear.py $D/n128_l* $D/H4_* $D/H8_* $D/n256_l* $D/ca0.1_* --csv $D/sweep.csv --plot $D/vesicle_shear.png | tee $D/sweep.txt
      /usr/bin/python3 scripts/vesicle_shear.py $D/semi_implicit/* --csv $D/semi_implicit.csv | tee $D/semi_implicit.txt ;;
    vesicle_published)  # (one thread per run: the two cores are shared)
      # the ellipse of reduced area 0.66 and R0 = 0.4 (scripts/vesicle_theory.py points --nu 0.66), uniform in arclength
      V=(env OMP_NUM_THREADS=1 build/sphib run cases/vesicle_shear.toml --quiet --set membrane.shape=ellipse
         --set membrane.spacing=arclength --set membrane.rx=0.6951643 --set membrane.ry=0.2301614)
      H4=(--set grid.nx=256 --set grid.ny=128 --set 'domain.x=[-4.0, 4.0]' --set 'domain.y=[-2.0, 2.0]'
          --set 'walls.bottom=[-2.0, 0.0]' --set 'walls.top=[2.0, 0.0]')  # H = 4 (confinement 0.2), same dx
      REF=cases/reference/quaife_biros_vesicle_inclination_ra066.csv
      D=$OUT/vesicle_published
      mkdir -p $D
      /usr/bin/python3 scripts/vesicle_theory.py angle --nu 0.66 --lam 0.5,1,2,3,3.5,4,4.5,5 | tee $D/theory.txt
      for l in 1 2 3 4 5; do "${V[@]}" --set membrane.viscosity_ratio=$l --out $D/n128_l$l; done
      for l in 1 3 4; do "${V[@]}" "${H4[@]}" --set membrane.viscosity_ratio=$l --out $D/H4_n128_l$l; done
      H8=(--set grid.nx=512 --set grid.ny=256 --set 'domain.x=[-8.0, 8.0]' --set 'domain.y=[-4.0, 4.0]'
          --set 'walls.bottom=[-4.0, 0.0]' --set 'walls.top=[4.0, 0.0]')  # H = 8 (confinement 0.1)
      "${V[@]}" "${H8[@]}" --set membrane.viscosity_ratio=3 --out $D/H8_n128_l3_t20  # 19 min
      "${V[@]}" "${H8[@]}" --set membrane.viscosity_ratio=4 --set time.end=14 --out $D/H8_n128_l4  # 17 min
      for l in 4.5 5; do "${V[@]}" "${H8[@]}" --set membrane.viscosity_ratio=$l --out $D/H8_n128_l$l; done  # 15, 18 min
      env OMP_NUM_THREADS=1 build/sphib run --restart $D/H8_n128_l4.5/checkpoint.h5 --set time.end=24 --quiet \
        --out $D/H8_n128_l4.5_t24  # its flip (-90 degrees at t = 20.4)
      H16=(--set grid.nx=1024 --set grid.ny=512 --set 'domain.x=[-16.0, 16.0]' --set 'domain.y=[-8.0, 8.0]'
           --set 'walls.bottom=[-8.0, 0.0]' --set 'walls.top=[8.0, 0.0]')  # H = 16 (confinement 0.05)
      for l in 3 4; do "${V[@]}" "${H16[@]}" --set membrane.viscosity_ratio=$l --out $D/H16_n128_l$l; done  # 44, 42 min
      "${V[@]}" --set membrane.Eb=0.0064 --out $D/ca10_n128_l1
      /usr/bin/python3 scripts/vesicle_shear.py $D/n128_l* $D/H4_* $D/H8_* $D/H16_* $D/ca10_* --reference $REF --nu 0.66 \
        --csv $D/sweep.csv --plot $D/vesicle_published.png | tee $D/sweep.txt ;;
    *) echo "validate: unknown section $s" >&2; exit 2 ;;
  esac
done
