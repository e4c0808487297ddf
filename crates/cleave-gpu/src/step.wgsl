// The explicit step of cleave on a GPU: one-point hexahedra (Flanagan-Belytschko hourglass
// control, bulk viscosity, Hughes-Winget objective update, elastic and bilinear plastic
// materials, each part's hourglass control and bulk viscosity), the time step, the
// central-difference update with body loads, concentrated and pressure loads, SPC and
// prescribed nodal motion, and the energy ledger. A port of the CPU step (cleave-core:
// element/kernel.rs, element/hex8.rs, material/, solver.rs), operation for operation; the
// Rust doc comments there carry the formulas and their sources.
//
// One step is six dispatches, each a no-op once `halt` is set:
//   positions (per node)  x^n = x^(n-1) + dt v^(n-1/2), if a step is pending
//   commit (1 thread)     t, dt_prev, step; body acceleration at t^n and t^(n-1)
//   elements (per elem)   stress update, corner forces, element time step; group partials
//   control (1 group)     smallest time step and energy sums (fixed tree); dt^(n+1/2)
//   nodes (per node)      force gather in a fixed order, v^(n+1/2), constraints and rigid
//                         walls; partials
//   finish (1 group)      kinetic energy, external work; halts at output times and errors
// Every sum is taken in a fixed order (no float atomics): the same bits on every run.

struct Params {
    ne: u32,
    nn: u32,
    groups_e: u32,
    groups_n: u32,
    n_body: u32,
    body_off: u32,
    mot_off: u32,
    pad0: u32,
    n_walls: u32,
    wall_off: u32,
    // values each node adds up for the ledger: 6 (kinetic energy, momentum, the work of the
    // constraints before and after t^n), then 4 per rigid wall (normal impulse, impulse)
    n_part: u32,
    pad: u32,
}

@group(0) @binding(0) var<storage, read_write> cf: array<f64>;
@group(0) @binding(1) var<storage, read_write> cu: array<atomic<u32>>;
@group(0) @binding(2) var<storage, read> par: array<f64>;
@group(0) @binding(3) var<storage, read> conn: array<u32>;
@group(0) @binding(4) var<storage, read> emat: array<u32>;
@group(0) @binding(5) var<storage, read_write> xs: array<f64>;
@group(0) @binding(6) var<storage, read_write> vs: array<f64>;
@group(0) @binding(7) var<storage, read_write> vns: array<f64>;
@group(0) @binding(8) var<storage, read> mass: array<f64>;
@group(0) @binding(9) var<storage, read_write> sig: array<f64>;
@group(0) @binding(10) var<storage, read_write> hist: array<f64>;
@group(0) @binding(11) var<storage, read_write> hgf: array<f64>;
@group(0) @binding(12) var<storage, read_write> bq: array<f64>;
@group(0) @binding(13) var<storage, read_write> fe_lo: array<f64>;
@group(0) @binding(14) var<storage, read_write> fe_hi: array<f64>;
@group(0) @binding(15) var<storage, read_write> epart: array<f64>;
@group(0) @binding(16) var<storage, read> nptr: array<u32>;
@group(0) @binding(17) var<storage, read> ninc: array<u32>;
@group(0) @binding(18) var<storage, read> nflag: array<u32>;
@group(0) @binding(19) var<storage, read> mptr: array<u32>;
@group(0) @binding(20) var<storage, read_write> npart: array<f64>;
@group(0) @binding(21) var<uniform> prm: Params;

// cf: control floats (host side: gpu::control)
const T: u32 = 0u;
const DT_PREV: u32 = 1u;
const DT: u32 = 2u;
const STEP: u32 = 3u;
const DT_FLOOR: u32 = 4u;
const E_INT: u32 = 5u;
const E_HG: u32 = 6u;
const E_KIN: u32 = 7u;
const E_EXT: u32 = 8u;
const PENDING_WORK: u32 = 9u;
const E_INIT: u32 = 10u;
const T_STOP: u32 = 11u;
const G_NOW: u32 = 12u;
const G_PREV: u32 = 15u;
const TSSFAC: u32 = 18u;
const DT_INIT: u32 = 19u;
const DT_MIN: u32 = 20u;
const END_TIME: u32 = 21u;
const DT_MID: u32 = 26u;
const W_HALF: u32 = 27u;
const DT_CRIT: u32 = 28u;
const WALL_FORCE: u32 = 32u; // 4 per wall: normal force, force x y z
// cu: control integers
const HALT: u32 = 0u;      // 0 running, 1 output due, 2 finished, 3 error
const ERROR: u32 = 1u;     // 1 inverted element, 2 time step below the floor, 3 bad time step, 4 non-finite
const INVERTED: u32 = 2u;  // lowest inverted element (atomic min)
const NONFINITE: u32 = 3u; // lowest node with a non-finite velocity (atomic min)
const DT_ELEM: u32 = 4u;
const PENDING_X: u32 = 5u;
const FINISHED: u32 = 6u;

const MAT_STRIDE: u32 = 13u;
const NODE_STRIDE: u32 = 8u;
const BIG: f64 = 1.7976931348623157e308lf;

fn halted() -> bool {
    return atomicLoad(&cu[HALT]) != 0u;
}

fn finite(x: f64) -> bool {
    return abs(x) <= BIG;
}

// ---------------------------------------------------------------- curves (cleave-core curve.rs)

// A curve at offset o of `par`: n, t_0..t_(n-1), y_0..y_(n-1); constant outside its range.
fn curve_eval(o: u32, t: f64) -> f64 {
    let n = u32(par[o]);
    if (n == 0u) {
        return 0.0lf;
    }
    let ts = o + 1u;
    let ys = o + 1u + n;
    if (t <= par[ts]) {
        return par[ys];
    }
    if (t >= par[ts + n - 1u]) {
        return par[ys + n - 1u];
    }
    var i = 1u;
    while (i < n - 1u && par[ts + i] <= t) {
        i = i + 1u;
    }
    let t0 = par[ts + i - 1u];
    let t1 = par[ts + i];
    let y0 = par[ys + i - 1u];
    let y1 = par[ys + i];
    return y0 + (y1 - y0) * (t - t0) / (t1 - t0);
}

// Base acceleration of the body loads at t: each load at body_off + 3k is (axis, curve offset
// or -1 for a constant 1, SF), and adds -SF curve(t) along its axis.
fn body_acceleration(t: f64) -> vec3<f64> {
    var g = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    for (var k = 0u; k < prm.n_body; k = k + 1u) {
        let o = prm.body_off + 3u * k;
        let axis = u32(par[o]);
        var c = 1.0lf;
        if (par[o + 1u] >= 0.0lf) {
            c = curve_eval(u32(par[o + 1u]), t);
        }
        g[axis] = g[axis] + -par[o + 2u] * c;
    }
    return g;
}

// ---------------------------------------------------------------- small matrices (row major)

alias M3 = array<vec3<f64>, 3>;

fn det3(a: M3) -> f64 {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

// Inverse, given the determinant d (checked positive and finite by the caller).
fn inv3(a: M3, d: f64) -> M3 {
    let i = 1.0lf / d;
    return M3(
        vec3<f64>((a[1][1] * a[2][2] - a[1][2] * a[2][1]) * i,
                  (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * i,
                  (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * i),
        vec3<f64>((a[1][2] * a[2][0] - a[1][0] * a[2][2]) * i,
                  (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * i,
                  (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * i),
        vec3<f64>((a[1][0] * a[2][1] - a[1][1] * a[2][0]) * i,
                  (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * i,
                  (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * i));
}

fn mul3(a: M3, b: M3) -> M3 {
    var c: M3;
    for (var i = 0u; i < 3u; i = i + 1u) {
        for (var j = 0u; j < 3u; j = j + 1u) {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    return c;
}

fn transpose3(a: M3) -> M3 {
    return M3(vec3<f64>(a[0][0], a[1][0], a[2][0]),
              vec3<f64>(a[0][1], a[1][1], a[2][1]),
              vec3<f64>(a[0][2], a[1][2], a[2][2]));
}

alias S6 = array<f64, 6>;

// sigma <- R sigma R^T (symmetric part, LS-DYNA order xx yy zz xy yz zx)
fn rotate_sym(r: M3, s: S6) -> S6 {
    let m = M3(vec3<f64>(s[0], s[3], s[5]), vec3<f64>(s[3], s[1], s[4]), vec3<f64>(s[5], s[4], s[2]));
    let o = mul3(mul3(r, m), transpose3(r));
    return S6(o[0][0], o[1][1], o[2][2], 0.5lf * (o[0][1] + o[1][0]),
              0.5lf * (o[1][2] + o[2][1]), 0.5lf * (o[2][0] + o[0][2]));
}

// Hughes-Winget R = I + 2/(1+s) (S + S^2), S the skew matrix of w, s = |w|^2.
fn hughes_winget(w: vec3<f64>) -> M3 {
    let s2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    let c = 2.0lf / (1.0lf + s2);
    let x = w[0];
    let y = w[1];
    let z = w[2];
    return M3(
        vec3<f64>(1.0lf + c * (x * x - s2), c * (-z + x * y), c * (y + x * z)),
        vec3<f64>(c * (z + y * x), 1.0lf + c * (y * y - s2), c * (-x + y * z)),
        vec3<f64>(c * (-y + z * x), c * (x + z * y), 1.0lf + c * (z * z - s2)));
}

fn ddot6(s: S6, t: S6) -> f64 {
    return s[0] * t[0] + s[1] * t[1] + s[2] * t[2] + 2.0lf * (s[3] * t[3] + s[4] * t[4] + s[5] * t[5]);
}

// Cube root: an f32 first guess, two Halley steps and a Newton step (cleave-core math::cbrt).
fn cbrt64(x: f64) -> f64 {
    var y = f64(pow(f32(x), 1.0 / 3.0));
    for (var k = 0; k < 2; k = k + 1) {
        let y3 = y * y * y;
        y = y * (y3 + 2.0lf * x) / (2.0lf * y3 + x);
    }
    return y - (y * y * y - x) / (3.0lf * y * y);
}

// ---------------------------------------------------------------- the hexahedron (hex8.rs)

// The corners' natural coordinates s_a (hex8.rs CORNERS) and the hourglass base vectors
// (GAMMA: eta zeta, zeta xi, xi eta, xi eta zeta at the corners), as arithmetic on the corner
// number: constant once the compiler unrolls the corner loops, with no table in memory.
fn sx(a: u32) -> f64 {
    return select(-1.0lf, 1.0lf, ((a ^ (a >> 1u)) & 1u) != 0u);
}
fn sy(a: u32) -> f64 {
    return select(-1.0lf, 1.0lf, (a & 2u) != 0u);
}
fn sz(a: u32) -> f64 {
    return select(-1.0lf, 1.0lf, (a & 4u) != 0u);
}
fn gamma_base(al: u32, a: u32) -> f64 {
    if (al == 0u) {
        return sy(a) * sz(a);
    }
    if (al == 1u) {
        return sz(a) * sx(a);
    }
    if (al == 2u) {
        return sx(a) * sy(a);
    }
    return sx(a) * sy(a) * sz(a);
}

// |d1 x d2|^2 of a face's diagonals (hex8.rs diagonal_cross): twice its area, squared.
fn face_c2(p0: vec3<f64>, p1: vec3<f64>, p2: vec3<f64>, p3: vec3<f64>) -> f64 {
    let c = cross(p2 - p0, p3 - p1);
    return dot(c, c);
}

alias P8 = array<vec3<f64>, 8>;

// Centre Jacobian J(0)[i][k] = 1/8 sum_a p_a[i] s_a[k], as rows.
fn centre_jacobian(p: P8) -> M3 {
    let c0 = 0.125lf * (-p[0] + p[1] + p[2] - p[3] - p[4] + p[5] + p[6] - p[7]);
    let c1 = 0.125lf * (-p[0] - p[1] + p[2] + p[3] - p[4] - p[5] + p[6] + p[7]);
    let c2 = 0.125lf * (-p[0] - p[1] - p[2] - p[3] + p[4] + p[5] + p[6] + p[7]);
    return M3(vec3<f64>(c0[0], c1[0], c2[0]), vec3<f64>(c0[1], c1[1], c2[1]), vec3<f64>(c0[2], c1[2], c2[2]));
}

fn positive(d: f64) -> bool {
    return d > 0.0lf && finite(d);
}

// ---------------------------------------------------------------- materials (material/)

struct Mat {
    density: f64,
    lambda: f64,
    shear: f64,
    wave_speed: f64,
    step_speed: f64,
    law: f64,
    sigy: f64,
    hp: f64,
    beta: f64,
    // the part's element controls: hourglass form (0 viscous, 1 stiffness), QH, Q1, Q2
    hg: f64,
    qh: f64,
    q1: f64,
    q2: f64,
}

fn material(m: u32) -> Mat {
    let o = m * MAT_STRIDE;
    return Mat(par[o], par[o + 1u], par[o + 2u], par[o + 3u], par[o + 4u], par[o + 5u],
               par[o + 6u], par[o + 7u], par[o + 8u], par[o + 9u], par[o + 10u], par[o + 11u],
               par[o + 12u]);
}

struct Point {
    sigma: S6,
    eps_p: f64,
    back: S6,
}

fn update_elastic(lambda: f64, g: f64, s: S6, d: S6) -> S6 {
    let lt = lambda * (d[0] + d[1] + d[2]);
    let g2 = 2.0lf * g;
    return S6(s[0] + (lt + g2 * d[0]), s[1] + (lt + g2 * d[1]), s[2] + (lt + g2 * d[2]),
              s[3] + g2 * d[3], s[4] + g2 * d[4], s[5] + g2 * d[5]);
}

// *MAT_ELASTIC (law 0) and *MAT_PLASTIC_KINEMATIC (law 1, radial return with mixed hardening).
fn update_material(m: Mat, p: Point, d: S6) -> Point {
    var o = p;
    o.sigma = update_elastic(m.lambda, m.shear, p.sigma, d);
    if (m.law < 0.5lf) {
        return o;
    }
    let s = o.sigma;
    let pr = (s[0] + s[1] + s[2]) / 3.0lf;
    let a = p.back;
    let xi = S6(s[0] - pr - a[0], s[1] - pr - a[1], s[2] - pr - a[2], s[3] - a[3], s[4] - a[4], s[5] - a[5]);
    let q = sqrt(1.5lf * ddot6(xi, xi));
    let sy = m.sigy + m.beta * m.hp * p.eps_p;
    let f = q - sy;
    if (f <= 0.0lf) {
        return o;
    }
    let deps_p = f / (3.0lf * m.shear + m.hp);
    let shrink = 3.0lf * m.shear * deps_p / q;
    let dalpha = (1.0lf - m.beta) * m.hp * deps_p / q;
    for (var i = 0u; i < 6u; i = i + 1u) {
        o.sigma[i] = o.sigma[i] - shrink * xi[i];
        o.back[i] = o.back[i] + dalpha * xi[i];
    }
    o.eps_p = p.eps_p + deps_p;
    return o;
}

// ---------------------------------------------------------------- the element pass (kernel.rs)

var<workgroup> r_dt: array<f64, 64>;
var<workgroup> r_id: array<u32, 64>;
var<workgroup> r_ei: array<f64, 64>;
var<workgroup> r_eh: array<f64, 64>;

fn ld(b: u32, n: u32) -> vec3<f64> {
    if (b == 0u) {
        return vec3<f64>(xs[3u * n], xs[3u * n + 1u], xs[3u * n + 2u]);
    }
    return vec3<f64>(vs[3u * n], vs[3u * n + 1u], vs[3u * n + 2u]);
}

struct ElemOut {
    ok: bool,
    dt: f64,
    de_int: f64,
    de_hg: f64,
}

fn element(e: u32) -> ElemOut {
    var out = ElemOut(false, BIG, 0.0lf, 0.0lf);
    var x: P8;
    var v: P8;
    for (var a = 0u; a < 8u; a = a + 1u) {
        let n = conn[8u * e + a];
        x[a] = ld(0u, n);
        v[a] = ld(1u, n);
    }
    let m = material(emat[e]);
    let dt_prev = cf[DT_PREV];
    let q1 = m.q1;
    let q2 = m.q2;
    let stiff = m.hg > 0.5lf;
    let jn = centre_jacobian(x);
    let detn = det3(jn);
    if (!positive(detn)) {
        return out;
    }
    let jinv = inv3(jn, detn);
    let vol = 8.0lf * detn;
    let l_vol = cbrt64(vol);
    var b: P8;
    for (var a = 0u; a < 8u; a = a + 1u) {
        b[a] = 0.125lf * (sx(a) * jinv[0] + sy(a) * jinv[1] + sz(a) * jinv[2]);
    }
    let jv = centre_jacobian(v);

    // 1-4: stress update over the previous interval
    var p = Point(S6(sig[6u * e], sig[6u * e + 1u], sig[6u * e + 2u], sig[6u * e + 3u], sig[6u * e + 4u], sig[6u * e + 5u]),
                  hist[7u * e],
                  S6(hist[7u * e + 1u], hist[7u * e + 2u], hist[7u * e + 3u], hist[7u * e + 4u], hist[7u * e + 5u], hist[7u * e + 6u]));
    var de_int = 0.0lf;
    var q = 0.0lf;
    var eps_v_rate = 0.0lf;
    if (dt_prev > 0.0lf) {
        let h = 0.5lf * dt_prev;
        let jm = M3(jn[0] - h * jv[0], jn[1] - h * jv[1], jn[2] - h * jv[2]);
        let detm = det3(jm);
        if (!positive(detm)) {
            return out;
        }
        let jminv = inv3(jm, detm);
        let vol_mid = 8.0lf * detm;
        let l = mul3(jv, jminv);
        let d = S6(l[0][0] * dt_prev, l[1][1] * dt_prev, l[2][2] * dt_prev,
                   0.5lf * (l[0][1] + l[1][0]) * dt_prev, 0.5lf * (l[1][2] + l[2][1]) * dt_prev,
                   0.5lf * (l[2][0] + l[0][2]) * dt_prev);
        let hw = 0.25lf * dt_prev;
        let r = hughes_winget(vec3<f64>(hw * (l[2][1] - l[1][2]), hw * (l[0][2] - l[2][0]), hw * (l[1][0] - l[0][1])));
        p.sigma = rotate_sym(r, p.sigma);
        if (p.back[0] != 0.0lf || p.back[1] != 0.0lf || p.back[2] != 0.0lf || p.back[3] != 0.0lf || p.back[4] != 0.0lf || p.back[5] != 0.0lf) {
            p.back = rotate_sym(r, p.back);
        }
        let old = p.sigma;
        p = update_material(m, p, d);
        var avg: S6;
        for (var i = 0u; i < 6u; i = i + 1u) {
            avg[i] = 0.5lf * (old[i] + p.sigma[i]);
        }
        de_int = vol_mid * ddot6(avg, d);
        eps_v_rate = l[0][0] + l[1][1] + l[2][2];
        if (eps_v_rate < 0.0lf) {
            q = m.density * l_vol * (q1 * l_vol * eps_v_rate * eps_v_rate - q2 * m.wave_speed * eps_v_rate);
        }
        de_int = de_int - vol_mid * 0.5lf * (bq[e] + q) * eps_v_rate * dt_prev;
    }
    bq[e] = q;
    for (var i = 0u; i < 6u; i = i + 1u) {
        sig[6u * e + i] = p.sigma[i];
        hist[7u * e + 1u + i] = p.back[i];
    }
    hist[7u * e] = p.eps_p;

    // 5: corner forces f_a = -V (sigma - q I) b_a
    let s = S6(p.sigma[0] - q, p.sigma[1] - q, p.sigma[2] - q, p.sigma[3], p.sigma[4], p.sigma[5]);
    var f: P8;
    for (var a = 0u; a < 8u; a = a + 1u) {
        let ba = b[a];
        f[a] = vec3<f64>(-vol * (s[0] * ba[0] + s[3] * ba[1] + s[5] * ba[2]),
                         -vol * (s[3] * ba[0] + s[1] * ba[1] + s[4] * ba[2]),
                         -vol * (s[5] * ba[0] + s[4] * ba[1] + s[2] * ba[2]));
    }

    // 6: hourglass
    var gamma: array<array<f64, 8>, 4>;
    for (var al = 0u; al < 4u; al = al + 1u) {
        var gx = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
        for (var a = 0u; a < 8u; a = a + 1u) {
            gx = gx + gamma_base(al, a) * x[a];
        }
        for (var a = 0u; a < 8u; a = a + 1u) {
            gamma[al][a] = gamma_base(al, a) - (gx[0] * b[a][0] + gx[1] * b[a][1] + gx[2] * b[a][2]);
        }
    }
    var coef: f64;
    if (stiff) {
        var bb = 0.0lf;
        for (var a = 0u; a < 8u; a = a + 1u) {
            bb = bb + (b[a][0] * b[a][0] + b[a][1] * b[a][1] + b[a][2] * b[a][2]);
        }
        coef = m.qh * (m.lambda + 2.0lf * m.shear) * vol * bb / 8.0lf * dt_prev;
    } else {
        coef = m.qh * m.density * m.wave_speed * l_vol * l_vol / 4.0lf;
    }
    var de_hg = 0.0lf;
    for (var al = 0u; al < 4u; al = al + 1u) {
        var qd = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
        for (var a = 0u; a < 8u; a = a + 1u) {
            qd = qd + v[a] * gamma[al][a];
        }
        for (var i = 0u; i < 3u; i = i + 1u) {
            let k = 12u * e + 3u * al + i;
            let old = hgf[k];
            var fnew = coef * qd[i];
            if (stiff) {
                fnew = old + coef * qd[i];
            }
            hgf[k] = fnew;
            de_hg = de_hg + 0.5lf * (old + fnew) * qd[i] * dt_prev;
            for (var a = 0u; a < 8u; a = a + 1u) {
                f[a][i] = f[a][i] - fnew * gamma[al][a];
            }
        }
    }
    for (var a = 0u; a < 4u; a = a + 1u) {
        for (var i = 0u; i < 3u; i = i + 1u) {
            fe_lo[12u * e + 3u * a + i] = f[a][i];
            fe_hi[12u * e + 3u * a + i] = f[a + 4u][i];
        }
    }

    // 7: stable time step l_c / (Q + sqrt(Q^2 + c^2)), l_c = V / largest face area
    // the faces in hex8.rs FACES order
    var c2max = 0.0lf;
    c2max = max(c2max, face_c2(x[0], x[3], x[2], x[1]));
    c2max = max(c2max, face_c2(x[4], x[5], x[6], x[7]));
    c2max = max(c2max, face_c2(x[0], x[1], x[5], x[4]));
    c2max = max(c2max, face_c2(x[1], x[2], x[6], x[5]));
    c2max = max(c2max, face_c2(x[2], x[3], x[7], x[6]));
    c2max = max(c2max, face_c2(x[3], x[0], x[4], x[7]));
    let lc = vol / (0.5lf * sqrt(c2max));
    let c = m.step_speed;
    var qv = 0.0lf;
    if (eps_v_rate < 0.0lf) {
        qv = q2 * c + q1 * lc * abs(eps_v_rate);
    }
    out.dt = lc / (qv + sqrt(qv * qv + c * c));
    out.ok = true;
    out.de_int = de_int;
    out.de_hg = de_hg;
    return out;
}

@compute @workgroup_size(64)
fn elements(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
            @builtin(num_workgroups) nw: vec3<u32>) {
    let grp = wid.y * nw.x + wid.x;
    let e = 64u * grp + lid.x;
    let run = !halted();
    var dt = BIG;
    var id = 0xffffffffu;
    var ei = 0.0lf;
    var eh = 0.0lf;
    if (run && e < prm.ne) {
        let r = element(e);
        if (r.ok) {
            dt = r.dt;
            id = e;
            ei = r.de_int;
            eh = r.de_hg;
        } else {
            atomicMin(&cu[INVERTED], e);
        }
    }
    let l = lid.x;
    r_dt[l] = dt;
    r_id[l] = id;
    r_ei[l] = ei;
    r_eh[l] = eh;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s = s >> 1u) {
        if (l < s) {
            let o = l + s;
            if (r_dt[o] < r_dt[l] || (r_dt[o] == r_dt[l] && r_id[o] < r_id[l])) {
                r_dt[l] = r_dt[o];
                r_id[l] = r_id[o];
            }
            r_ei[l] = r_ei[l] + r_ei[o];
            r_eh[l] = r_eh[l] + r_eh[o];
        }
        workgroupBarrier();
    }
    if (l == 0u && run && grp < prm.groups_e) {
        let g = grp;
        epart[4u * g] = r_dt[0];
        epart[4u * g + 1u] = f64(r_id[0]);
        epart[4u * g + 2u] = r_ei[0];
        epart[4u * g + 3u] = r_eh[0];
    }
}

// ---------------------------------------------------------------- positions and commit

@compute @workgroup_size(64)
fn positions(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
             @builtin(num_workgroups) nw: vec3<u32>) {
    let n = 64u * (wid.y * nw.x + wid.x) + lid.x;
    if (n >= prm.nn || halted() || atomicLoad(&cu[PENDING_X]) == 0u) {
        return;
    }
    let dt = cf[DT];
    for (var i = 0u; i < 3u; i = i + 1u) {
        xs[3u * n + i] = xs[3u * n + i] + vs[3u * n + i] * dt;
    }
}

@compute @workgroup_size(1)
fn commit() {
    if (halted()) {
        return;
    }
    if (atomicLoad(&cu[PENDING_X]) != 0u) {
        cf[T] = cf[T] + cf[DT];
        cf[DT_PREV] = cf[DT];
        cf[STEP] = cf[STEP] + 1.0lf;
        atomicStore(&cu[PENDING_X], 0u);
    }
    let g = body_acceleration(cf[T]);
    let gp = body_acceleration(cf[T] - cf[DT_PREV]);
    for (var i = 0u; i < 3u; i = i + 1u) {
        cf[G_NOW + i] = g[i];
        cf[G_PREV + i] = gp[i];
    }
}

// ---------------------------------------------------------------- control: the time step

var<workgroup> c_dt: array<f64, 256>;
var<workgroup> c_id: array<u32, 256>;
var<workgroup> c_ei: array<f64, 256>;
var<workgroup> c_eh: array<f64, 256>;

fn fail(kind: u32) {
    atomicStore(&cu[ERROR], kind);
    atomicStore(&cu[HALT], 3u);
}

@compute @workgroup_size(256)
fn control(@builtin(local_invocation_id) lid: vec3<u32>) {
    let run = !halted();
    let l = lid.x;
    var dt = BIG;
    var id = 0xffffffffu;
    var ei = 0.0lf;
    var eh = 0.0lf;
    if (run) {
        for (var g = l; g < prm.groups_e; g = g + 256u) {
            let d = epart[4u * g];
            let i = u32(epart[4u * g + 1u]);
            if (d < dt || (d == dt && i < id)) {
                dt = d;
                id = i;
            }
            ei = ei + epart[4u * g + 2u];
            eh = eh + epart[4u * g + 3u];
        }
    }
    c_dt[l] = dt;
    c_id[l] = id;
    c_ei[l] = ei;
    c_eh[l] = eh;
    workgroupBarrier();
    for (var s = 128u; s > 0u; s = s >> 1u) {
        if (l < s) {
            let o = l + s;
            if (c_dt[o] < c_dt[l] || (c_dt[o] == c_dt[l] && c_id[o] < c_id[l])) {
                c_dt[l] = c_dt[o];
                c_id[l] = c_id[o];
            }
            c_ei[l] = c_ei[l] + c_ei[o];
            c_eh[l] = c_eh[l] + c_eh[o];
        }
        workgroupBarrier();
    }
    if (l != 0u || !run) {
        return;
    }
    if (atomicLoad(&cu[INVERTED]) != 0xffffffffu) {
        fail(1u);
        return;
    }
    cf[E_INT] = cf[E_INT] + c_ei[0];
    cf[E_HG] = cf[E_HG] + c_eh[0];
    let dt_crit = c_dt[0];
    cf[DT_CRIT] = dt_crit;
    let step0 = cf[STEP] == 0.0lf;
    var d = cf[TSSFAC] * dt_crit;
    if (cf[DT_INIT] > 0.0lf && (step0 || !finite(dt_crit))) {
        d = min(d, cf[DT_INIT]);
    }
    atomicStore(&cu[DT_ELEM], c_id[0]);
    cf[DT] = d;
    if (step0) {
        cf[DT_FLOOR] = cf[DT_MIN] * d;
    } else if (d < cf[DT_FLOOR]) {
        fail(2u);
        return;
    }
    if (!finite(d) || d <= 0.0lf) {
        fail(3u);
        return;
    }
    let remaining = cf[END_TIME] - cf[T];
    if (remaining <= 1e-9lf * min(d, cf[END_TIME])) {
        atomicStore(&cu[FINISHED], 1u);
    } else if (d > remaining) {
        d = remaining;
    }
    cf[DT] = d;
    let dp = cf[DT_PREV];
    cf[DT_MID] = 0.5lf * (dp + d);
    var w = 0.0lf;
    if (step0) {
        w = 0.5lf;
    } else if (dp + d > 0.0lf) {
        w = dp / (dp + d);
    }
    cf[W_HALF] = w;
}

// ---------------------------------------------------------------- the nodes

const MAX_PART: u32 = 38u; // 6 + 4 x 8 rigid walls
var<workgroup> n_s: array<f64, 64>;

// What a constraint does to a node's velocity: the new v^(n+1/2), v^n kept consistent, and
// the work of the reaction impulse split into its halves before and after t^n
// (solver.rs constrain_velocity).
struct Constrained {
    v: vec3<f64>,
    vn: vec3<f64>,
    now: f64,
    later: f64,
}

fn constrain(m: f64, w: f64, v: vec3<f64>, vn: vec3<f64>, v_new: vec3<f64>) -> Constrained {
    let v_old = (vn - v * w) * (1.0lf / (1.0lf - w));
    let dv = v_new - v;
    let j = dv * m;
    return Constrained(v_new, vn + dv * w, 0.5lf * dot(j, v_old), 0.5lf * dot(j, v_new));
}

@compute @workgroup_size(64)
fn nodes(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
         @builtin(num_workgroups) nw: vec3<u32>) {
    let n = 64u * (wid.y * nw.x + wid.x) + lid.x;
    let run = !halted();
    // the ledger's six values (kept apart from the walls', which only a deck with walls
    // indexes at run time)
    var acc = array<f64, 6>(0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
    var wacc: array<f64, 32>;
    if (run && n < prm.nn) {
        let m = mass[n];
        let g = vec3<f64>(cf[G_NOW], cf[G_NOW + 1u], cf[G_NOW + 2u]);
        var f = g * m;
        for (var k = nptr[n]; k < nptr[n + 1u]; k = k + 1u) {
            let c = ninc[k];
            let e = c >> 3u;
            let a = c & 7u;
            if (a < 4u) {
                let o = 12u * e + 3u * a;
                f = f + vec3<f64>(fe_lo[o], fe_lo[o + 1u], fe_lo[o + 2u]);
            } else {
                let o = 12u * e + 3u * (a - 4u);
                f = f + vec3<f64>(fe_hi[o], fe_hi[o + 1u], fe_hi[o + 2u]);
            }
        }
        let t = cf[T];
        // the node's concentrated loads and pressure segments at t^n (loads.rs), summed apart
        // for their work
        var fl = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
        for (var k = mptr[n]; k < mptr[n + 1u]; k = k + 1u) {
            let o = prm.mot_off + NODE_STRIDE * k;
            let kind = par[o];
            if (kind < 0.5lf) {
                continue;
            }
            if (kind < 1.5lf) {
                fl[u32(par[o + 1u])] = fl[u32(par[o + 1u])] + par[o + 2u] * curve_eval(u32(par[o + 3u]), t);
                continue;
            }
            var p = 0.0lf;
            if (t >= par[o + 3u]) {
                p = par[o + 1u] * curve_eval(u32(par[o + 2u]), t);
            }
            if (p != 0.0lf) {
                let n3 = u32(par[o + 6u]);
                let n4 = u32(par[o + 7u]);
                var pts = 4.0lf;
                if (n4 == n3) {
                    pts = 3.0lf;
                }
                let x1 = ld(0u, u32(par[o + 4u]));
                let x2 = ld(0u, u32(par[o + 5u]));
                let area = cross(ld(0u, n3) - x1, ld(0u, n4) - x2) * 0.5lf;
                fl = fl + area * (-p / pts);
            }
        }
        f = f + fl;
        let dt_mid = cf[DT_MID];
        let dp = cf[DT_PREV];
        let dt = cf[DT];
        var w2 = 0.0lf;
        if (dt_mid > 0.0lf) {
            w2 = 0.5lf * dp / (dp + dt);
        }
        var dv = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
        if (m > 0.0lf) {
            dv = f * (dt_mid / m);
        }
        var v = ld(1u, n);
        // the loads' impulse F dt_mid: half its work on v^(n-1/2) now, half on v^(n+1/2) as
        // updated (before the constraints) at the next step, as the CPU books it
        acc[4] = acc[4] + 0.5lf * dot(fl, v) * dt_mid;
        var vn = v + dv * (2.0lf * w2);
        v = v + dv;
        acc[5] = acc[5] + 0.5lf * dot(fl, v) * dt_mid;
        let w = cf[W_HALF];
        // SPC, then the prescribed motions of the node in the deck's order
        let flags = nflag[n];
        let spc = flags & 7u;
        if (spc != 0u) {
            var vc = v;
            for (var i = 0u; i < 3u; i = i + 1u) {
                if ((spc & (1u << i)) != 0u) {
                    vc[i] = 0.0lf;
                }
            }
            let r = constrain(m, w, v, vn, vc);
            v = r.v;
            vn = r.vn;
            acc[4] = acc[4] + r.now;
            acc[5] = acc[5] + r.later;
        }
        for (var k = mptr[n]; k < mptr[n + 1u]; k = k + 1u) {
            let o = prm.mot_off + NODE_STRIDE * k;
            if (par[o] > 0.5lf) {
                continue;
            }
            let axis = u32(par[o + 1u]);
            let c = u32(par[o + 4u]);
            var vc = v;
            if (par[o + 2u] < 0.5lf) {
                vc[axis] = par[o + 3u] * curve_eval(c, t + 0.5lf * dt);
            } else {
                let goal = par[o + 5u] + par[o + 3u] * curve_eval(c, t + dt);
                vc[axis] = (goal - xs[3u * n + axis]) / dt;
            }
            let r = constrain(m, w, v, vn, vc);
            v = r.v;
            vn = r.vn;
            acc[4] = acc[4] + r.now;
            acc[5] = acc[5] + r.later;
        }
        // planar rigid walls (solver.rs apply_rigid_walls): a node that would cross a wall in
        // the next step lands on it; friction takes up to FRIC times the normal impulse
        for (var wl = 0u; wl < prm.n_walls; wl = wl + 1u) {
            if ((flags & (8u << wl)) == 0u) {
                continue;
            }
            let o = prm.wall_off + 7u * wl;
            let tail = vec3<f64>(par[o], par[o + 1u], par[o + 2u]);
            let nrm = vec3<f64>(par[o + 3u], par[o + 4u], par[o + 5u]);
            let fric = par[o + 6u];
            let gap = dot(ld(0u, n) - tail, nrm);
            let vnn = dot(v, nrm);
            if (gap + dt * vnn >= 0.0lf) {
                continue;
            }
            var vn_new = 0.0lf;
            if (gap >= 0.0lf) {
                vn_new = -gap / dt;
            }
            let dvn = vn_new - vnn;
            let vt = v - nrm * vnn;
            let vt_mag = sqrt(dot(vt, vt));
            var vt_new = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
            if (!(fric >= 1.0lf || vt_mag <= fric * dvn)) {
                vt_new = vt * (1.0lf - fric * dvn / vt_mag);
            }
            let v_new = nrm * vn_new + vt_new;
            let imp = (v_new - v) * m;
            wacc[4u * wl] = wacc[4u * wl] + m * dvn;
            for (var i = 0u; i < 3u; i = i + 1u) {
                wacc[4u * wl + 1u + i] = wacc[4u * wl + 1u + i] + imp[i];
            }
            let r = constrain(m, w, v, vn, v_new);
            v = r.v;
            vn = r.vn;
            acc[4] = acc[4] + r.now;
            acc[5] = acc[5] + r.later;
        }
        for (var i = 0u; i < 3u; i = i + 1u) {
            vs[3u * n + i] = v[i];
            vns[3u * n + i] = vn[i];
        }
        if (!finite(v[0]) || !finite(v[1]) || !finite(v[2])) {
            atomicMin(&cu[NONFINITE], n);
        }
        // leapfrog kinetic energy 1/2 m v^(n-1/2).v^(n+1/2), momentum m v^(n-1/2)
        let old = (vn - v * w) * (1.0lf / (1.0lf - w));
        acc[0] = 0.5lf * m * dot(old, v);
        acc[1] = m * old[0];
        acc[2] = m * old[1];
        acc[3] = m * old[2];
    }
    // each value summed over the group by a tree of fixed shape
    let l = lid.x;
    let g = wid.y * nw.x + wid.x;
    let keep = l == 0u && run && g < prm.groups_n;
    for (var k = 0u; k < 6u; k = k + 1u) {
        let s = group_sum(l, acc[k]);
        if (keep) {
            npart[prm.n_part * g + k] = s;
        }
    }
    for (var k = 0u; k < 4u * prm.n_walls; k = k + 1u) {
        let s = group_sum(l, wacc[k]);
        if (keep) {
            npart[prm.n_part * g + 6u + k] = s;
        }
    }
}

// The sum of `val` over the 64 threads of the group, by a tree of fixed shape (all threads
// must call it).
fn group_sum(l: u32, val: f64) -> f64 {
    n_s[l] = val;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s = s >> 1u) {
        if (l < s) {
            n_s[l] = n_s[l] + n_s[l + s];
        }
        workgroupBarrier();
    }
    let total = n_s[0];
    workgroupBarrier();
    return total;
}

// ---------------------------------------------------------------- finish: the ledger

var<workgroup> f_s: array<f64, 256>;
var<workgroup> f_tot: array<f64, MAX_PART>;

@compute @workgroup_size(256)
fn finish(@builtin(local_invocation_id) lid: vec3<u32>) {
    let run = !halted();
    let l = lid.x;
    for (var k = 0u; k < prm.n_part; k = k + 1u) {
        var acc = 0.0lf;
        if (run) {
            for (var g = l; g < prm.groups_n; g = g + 256u) {
                acc = acc + npart[prm.n_part * g + k];
            }
        }
        f_s[l] = acc;
        workgroupBarrier();
        for (var s = 128u; s > 0u; s = s >> 1u) {
            if (l < s) {
                f_s[l] = f_s[l] + f_s[l + s];
            }
            workgroupBarrier();
        }
        if (l == 0u) {
            f_tot[k] = f_s[0];
        }
        workgroupBarrier();
    }
    if (l != 0u || !run) {
        return;
    }
    let ke = f_tot[0];
    if (atomicLoad(&cu[NONFINITE]) != 0xffffffffu || !finite(ke)) {
        fail(4u);
        return;
    }
    cf[E_KIN] = ke;
    var body = 0.0lf;
    let dp = cf[DT_PREV];
    if (prm.n_body > 0u && dp != 0.0lf) {
        let g = vec3<f64>(cf[G_PREV], cf[G_PREV + 1u], cf[G_PREV + 2u]) + vec3<f64>(cf[G_NOW], cf[G_NOW + 1u], cf[G_NOW + 2u]);
        body = 0.5lf * dot(g, vec3<f64>(f_tot[1], f_tot[2], f_tot[3])) * dp;
    }
    cf[E_EXT] = cf[E_EXT] + cf[PENDING_WORK] + f_tot[4] + body;
    cf[PENDING_WORK] = f_tot[5];
    var inv = 0.0lf;
    if (cf[DT_MID] > 0.0lf) {
        inv = 1.0lf / cf[DT_MID];
    }
    for (var wl = 0u; wl < prm.n_walls; wl = wl + 1u) {
        for (var k = 0u; k < 4u; k = k + 1u) {
            cf[WALL_FORCE + 4u * wl + k] = f_tot[6u + 4u * wl + k] * inv;
        }
    }
    if (cf[STEP] == 0.0lf) {
        cf[E_INIT] = ke + cf[E_INT] + cf[E_HG] - cf[E_EXT];
    }
    atomicStore(&cu[PENDING_X], 1u);
    if (atomicLoad(&cu[FINISHED]) != 0u) {
        atomicStore(&cu[HALT], 2u);
    } else if (cf[T] >= cf[T_STOP] * (1.0lf - 1e-12lf)) {
        atomicStore(&cu[HALT], 1u);
    }
}
