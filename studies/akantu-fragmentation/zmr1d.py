#!/usr/bin/env python3
"""ZMR (Zhou-Molinari-Ramesh 2005) 1-D dynamic fragmentation with Akantu.

1-D bar of segment_2 elements; every interior node is a potential extrinsic
cohesive interface (cohesive_1d_2 inserted on demand by Akantu's
SolidMechanicsModelCohesive, material cohesive_linear = Camacho-Ortiz).
"""
import argparse, json, os, sys, time
import numpy as np
import akantu as aka
from mkmesh import write_msh

p = argparse.ArgumentParser()
p.add_argument("--rate", type=float, required=True, help="strain rate / eps_dot0")
p.add_argument("--seed", type=int, default=1)
p.add_argument("--nel", type=int, default=2000)
p.add_argument("--nL0", type=float, default=100.0)
p.add_argument("--dtfac", type=float, default=0.1, help="dt = dtfac * h/c")
p.add_argument("--penalty_fac", type=float, default=1.0, help="contact penalty = fac * E/h  [Pa/m]")
p.add_argument("--spread", type=float, default=0.10)
p.add_argument("--out", default="results")
a = p.parse_args()

E, rho, GC, sig = 275e9, 2750.0, 100.0, 300e6
c = np.sqrt(E / rho)
L0 = E * GC / sig**2
t0 = L0 / c
edot0 = c * sig**3 / (E**2 * GC)
edot = a.rate * edot0
L = a.nL0 * L0
h = L / a.nel
t_end = 1.1 * t0 / a.rate + 40 * t0
t_half = 1.1 * t0 / a.rate + 20 * t0

tag = f"r{a.rate:g}_s{a.seed}_n{a.nel}_dt{a.dtfac:g}_p{a.penalty_fac:g}"
wd = os.path.join(a.out, tag)
os.makedirs(wd, exist_ok=True)
msh = os.path.join(wd, "bar.msh"); dat = os.path.join(wd, "material.dat")
write_msh(msh, L, a.nel)
with open(dat, "w") as f:
    f.write(f"""
model solid_mechanics_model_cohesive [
  material elastic [
    name = bulk
    rho = {rho!r}
    E = {E!r}
    nu = 0
  ]
  material cohesive_linear [
    name = coh
    sigma_c = {sig!r}
    G_c = {GC!r}
    beta = 0
    penalty = {a.penalty_fac * E / h!r}
    contact_after_breaking = true
  ]
]
""")
aka.parseInput(dat)
mesh = aka.Mesh(1)
mesh.read(msh)
model = aka.SolidMechanicsModelCohesive(mesh)
model.initFull(_analysis_method=aka._explicit_lumped_mass, _is_extrinsic=True)

coh = model.getMaterial(1)
# random strengths: one independent uniform value per facet (interface)
sc = coh.getInternalReal("sigma_c")(aka._point_1)
rng = np.random.default_rng(a.seed)
sc[:, 0] = sig * (1.0 + a.spread * rng.uniform(-1.0, 1.0, sc.shape[0]))
del sc  # do not keep numpy views on Akantu arrays (they can be reallocated)

dt_crit = model.getStableTimeStep()
dt = a.dtfac * dt_crit
model.setTimeStep(dt)
nsteps = int(np.ceil(t_end / dt - 1e-9))
n_half = int(round(t_half / dt))

X = mesh.getNodes()[:, 0].copy()
iL = int(np.argmin(X)); iR = int(np.argmax(X))
u = model.getDisplacement(); v = model.getVelocity(); blk = model.getBlockedDOFs()
v[:, 0] = edot * (X - L / 2)
vL, vR = -edot * L / 2, edot * L / 2
blk[iL, 0] = True; blk[iR, 0] = True
del u, v, blk

def n_open():
    try:
        d = coh.getInternalReal("damage")(aka._cohesive_1d_2)
    except Exception:
        return 0, 0
    d = np.asarray(d).ravel()
    return int(np.sum(d >= 1.0 - 1e-12)), d.size

def energies():
    global Wext
    out = {"Wext": Wext}
    for k in ("kinetic", "potential", "dissipated", "reversible", "contact"):
        try:
            out[k] = float(model.getEnergy(k))
        except Exception as e:
            out[k] = None
    return out

hist = []
res = {"rate": a.rate, "seed": a.seed, "nel": a.nel, "h": h, "L0": L0, "t0": t0,
       "edot": edot, "dt": dt, "dt_crit": dt_crit, "nsteps": nsteps,
       "penalty": a.penalty_fac * E / h, "akantu": getattr(aka, "__version__", "?")}
tic = time.time()
Wext = 0.0
contact = {"sampled_every": 10, "steps_with_contact": 0, "max_contact_traction_MPa": 0.0, "max_elems_in_contact": 0}
KE0 = float(model.getEnergy("kinetic"))
res["KE0"] = KE0
for s in range(nsteps):
    t1 = (s + 1) * dt
    # arrays are re-fetched every step: cohesive insertion duplicates nodes and
    # reallocates the nodal arrays, so old numpy views would dangle
    u = model.getDisplacement(); v = model.getVelocity()
    u[iL, 0] = vL * t1; u[iR, 0] = vR * t1
    v[iL, 0] = vL; v[iR, 0] = vR
    del u, v
    model.checkCohesiveStress()
    model.solveStep()
    fi = model.getInternalForce()
    # reaction supplied by the velocity BC at the blocked end nodes (a = 0 there)
    Wext += dt * (-fi[iL, 0] * vL - fi[iR, 0] * vR)
    del fi
    if (s + 1) % 10 == 0:
        try:
            ct = np.asarray(coh.getInternalReal("contact_tractions")(aka._cohesive_1d_2)).ravel()
            if ct.size and np.abs(ct).max() > 0:
                contact["steps_with_contact"] += 1
                contact["max_contact_traction_MPa"] = max(contact["max_contact_traction_MPa"], np.abs(ct).max() / 1e6)
                contact["max_elems_in_contact"] = max(contact["max_elems_in_contact"], int(np.sum(ct != 0)))
        except Exception:
            pass
    if (s + 1) % max(1, nsteps // 40) == 0 or s + 1 == n_half or s + 1 == nsteps:
        nb, ni = n_open()
        en = energies()
        hist.append({"step": s + 1, "t_over_t0": t1 / t0, "broken": nb, "inserted": ni, **en})
        print(f"step {s+1}/{nsteps} t/t0={t1/t0:.3f} inserted={ni} open={nb} "
              f"frag={nb+1} Ediss={en['dissipated']} wall={time.time()-tic:.1f}s", flush=True)
    if s + 1 == n_half:
        nb, ni = n_open()
        res["half"] = {"t_over_t0": t1 / t0, "fragments": nb + 1, "inserted": ni,
                       "mean_size_L0": a.nL0 / (nb + 1), **energies()}
nb, ni = n_open()
res["end"] = {"t_over_t0": nsteps * dt / t0, "fragments": nb + 1, "inserted": ni,
              "mean_size_L0": a.nL0 / (nb + 1), **energies()}
try:
    se = np.asarray(coh.getInternalReal("sigma_c_eff")(aka._cohesive_1d_2)).ravel()
    res["sigma_c_eff_MPa"] = {"min": se.min() / 1e6, "mean": se.mean() / 1e6, "max": se.max() / 1e6}
except Exception as ex:
    res["sigma_c_eff_MPa"] = str(ex)
sc_all = np.asarray(coh.getInternalReal("sigma_c")(aka._point_1)).ravel()
res["sigma_c_facets_MPa"] = {"n": int(sc_all.size), "min": sc_all.min() / 1e6, "max": sc_all.max() / 1e6}
d = np.asarray(coh.getInternalReal("damage")(aka._cohesive_1d_2)).ravel()
res["damage_end"] = {"n_inserted": int(d.size), "d>=1": int(np.sum(d >= 1 - 1e-12)), "d>=0.9": int(np.sum(d >= 0.9)),
                     "d>=0.5": int(np.sum(d >= 0.5)), "d>0": int(np.sum(d > 0))}
res["contact"] = contact
res["wall_s"] = time.time() - tic
res["history"] = hist
# Wext approx, and dissipated per broken-interface check
res["GC_times_open"] = GC * nb
json.dump(res, open(os.path.join(wd, "result.json"), "w"), indent=1)
print(json.dumps({k: v for k, v in res.items() if k != "history"}, indent=1))
