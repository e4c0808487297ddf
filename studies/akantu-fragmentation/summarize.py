import json, glob, sys, numpy as np
pat = sys.argv[1] if len(sys.argv) > 1 else "results/*_n2000_dt0.1_p1/result.json"
rows = {}
print("| rate | seed | dt_fac | penalty_fac | n_el | frag @half | frag @end | mean size @end [L0] | inserted | E_diss @end [J/m^2] | E_diss/GC [interfaces-equiv.] | energy-balance err [J/m^2] | wall [s] |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for f in sorted(glob.glob(pat)):
    r = json.load(open(f)); e = r["end"]; hf = r["half"]
    bal = r["KE0"] + e["Wext"] - (e["kinetic"] + e["potential"] + e["dissipated"] + e["reversible"] + e["contact"])
    rows.setdefault(r["rate"], []).append((hf["fragments"], e["fragments"], e["dissipated"]))
    print(f"| {r['rate']:g} | {r['seed']} | {r['dt']/r['dt_crit']:.2g} | {r['penalty']*r['h']/275e9:.3g} | {r['nel']} | {hf['fragments']} | {e['fragments']} | {e['mean_size_L0']:.3f} | {e['inserted']} | {e['dissipated']:.0f} | {e['dissipated']/100:.1f} | {bal:.1f} | {r['wall_s']:.1f} |")
print()
print("| rate | mean frag @half | mean frag @end | mean size @end [L0] (=100/mean count) | mean E_diss [J/m^2] | ZMR fit [L0] |")
print("|---|---|---|---|---|---|")
for k in sorted(rows):
    a = np.array(rows[k], float)
    print(f"| {k:g} | {a[:,0].mean():.1f} | {a[:,1].mean():.1f} | {100/a[:,1].mean():.3f} | {a[:,2].mean():.0f} | {4.5/(1+4.5*k**(2/3)):.3f} |")
