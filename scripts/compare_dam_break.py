# Compares dam-break runs with a reference run (docs/validation/isph.md):
#   /usr/bin/python3 scripts/compare_dam_break.py REF_RUN RUN...
# per run its summary figures, and against REF_RUN on REF_RUN's diagnostics times the rms
# difference of front_x and of each load (also after a 5-sample running mean: without the
# single-step spikes), and the profile's phases above 0.5 s.
import sys, json, numpy as np, csv
def load(d):
    r = list(csv.DictReader(open(d + '/diagnostics.csv')))
    a = {k: np.array([float(x[k]) for x in r]) for k in r[0]}
    s = json.load(open(d + '/summary.json'))
    return a, s
ref, rs = load(sys.argv[1])
def smooth(v, n=5):  # 5-sample (6 ms) running mean: the loads without single-step spikes
    return np.convolve(v, np.ones(n) / n, mode='same')
keys = ['front_deviation_koshizuka_oka_1996', 'front_deviation_martin_moyce_1952_a1_125in', 'front_deviation_martin_moyce_1952_a2_25in',
        'load_left_min', 'load_right_max', 'load_right_max_t', 'load_bottom_max', 'poisson_cg_iterations',
        'poisson_preconditioner_factorisations', 'seconds_per_step', 'wall_seconds', 'verlet_builds']
for d in sys.argv[1:]:
    a, s = load(d)
    n = len(ref['t'])
    a = {k: np.interp(ref['t'], a['t'], v) for k, v in a.items()}  # onto the reference's times
    line = [d]
    for k in keys: line.append(f"{k.replace('front_deviation_','fd_')}={s.get(k, float('nan')):.4g}")
    m = ref['t'][:n] <= 0.6
    line.append(f"front_rms_vs_ref={np.sqrt(np.mean((a['front_x'][:n]-ref['front_x'][:n])**2)):.3g}")
    for w in ['left', 'right', 'bottom']:
        k = 'load_' + w
        line.append(f"{k}_rms_vs_ref={np.sqrt(np.mean((a[k][:n]-ref[k][:n])**2)):.3g}"
                    f"(smoothed {np.sqrt(np.mean((smooth(a[k][:n])-smooth(ref[k][:n]))**2)):.3g})")
    p = s.get('profile_seconds', {})
    line.append('profile: ' + ', '.join(f"{k.split(' (')[0]}={v:.1f}" for k, v in p.items() if v > 0.5))
    print('\n  '.join(line))
