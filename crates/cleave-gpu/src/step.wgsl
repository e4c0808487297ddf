// The explicit step of cleave on a GPU: one-point hexahedra and wedges (Flanagan-Belytschko
// hourglass control), fully integrated selectively reduced hexahedra, constant-strain
// tetrahedra and those with nodal pressure averaging, bulk viscosity, the Hughes-Winget
// objective update, every deformable material (elastic, bilinear plastic, Johnson-Cook with its
// equations of state, piecewise linear), each part's hourglass control and bulk viscosity,
// rigid bodies, the time step, the central-difference update with body, concentrated and
// pressure loads, SPC and prescribed nodal motion, rigid walls, and the energy ledger. A port
// of the CPU step (cleave-core: element/kernel.rs, element/hex8.rs, element/tet4.rs,
// element/sri.rs, element/nodal_pressure.rs, material/, rigid.rs, solver.rs), operation for
// operation; the Rust doc comments there carry the formulas and their sources.
//
// One step is four dispatches, five with rigid bodies, two or three more with separation
// (four more with ELFORM 13: np_theta and np_node_theta before the elements, np_node_p and
// np_correct after), each a no-op once `halt` is set:
//   elements (per elem)   stress update, corner forces, element time step; group partials
//   erosion_done (1 thread, with contact and erosion)  halts the step if elements eroded
//                         (HALT 5: the host changes the contact surfaces, runs the rest)
//   interfaces (per interface, with separation)  the failure check; interfaces_done
//                         (1 thread) halts the step if one failed (HALT 4: the host splits
//                         the sets and runs the rest of the step)
//   cohesive (per softening face, with MODELs 3 and 4)  tractions, forces, work, springs
//   contact.wgsl's passes (with *CONTACT_AUTOMATIC_...; a bind group of their own; nine,
//                         eleven with separation: the closed cracks' step, which halts the
//                         step when one is released, HALT 6) each node's contact force at t^n
//                         into `fcon`, the contact energy
//   control (1 group)     smallest time step (and the cohesive springs') and energy sums
//                         (fixed tree); dt^(n+1/2)
//   rigid (1 group/body)  force and moment of each rigid body (fixed tree), its 6-dof update
//   nodes (per node)      force gather in a fixed order, v^(n+1/2), rigid bodies' nodes
//                         placed, constraints and rigid walls; partials; x^(n+1) = x^n +
//                         dt v^(n+1/2) into the other half of the positions (halves)
//   finish (1 group)      kinetic energy, external work; halts at output times and errors;
//                         else ends the step (advance: t, dt_prev, step, the rigid bodies'
//                         placements, body accelerations at t^(n+1) and t^n)
// and each batch of steps starts with
//   commit (1 thread)     the end of a step that halted (COMMIT_DUE), so that the host read
//                         the state at t^n; the body accelerations at the start of a run
// (A batch that runs through leaves the control block one step on: t^(n+1), the progress bar's
// time; a halt leaves it at t^n.) After a restart file is taken up, the positions pass
// (per node) writes the x^(n+1) of the step its state had begun.
// Every sum is taken in a fixed order (no float atomics): the same bits on every run. The
// per-node passes (nodes, positions) run over the entries in use, `cf[SLOTS]`: every node, or
// with separation the coincident sets' slots (separation.rs; an indirect dispatch).
//
// The host puts the model's features before this text as constants (layout.rs
// shader_constants: HAS_RIGID, HAS_TET, HAS_SRI, HAS_EROSION, LAWS, WALL_VALUES); the paths a model does not
// use are constant-false branches that the driver drops, so their registers do not weigh on
// the kernels of the others. Before them: `contact_force(n)`, which reads the contact's `fcon`
// (binding 32) or, without contact, is zero (contact.rs step_prefix); then math.wgsl.

struct Params {
    ne: u32,
    nn: u32,
    groups_e: u32,
    groups_n: u32,
    n_body: u32,
    body_off: u32,
    mot_off: u32,
    n_rigid: u32,
    n_walls: u32,
    wall_off: u32,
    // values each node adds up for the ledger: 6 (kinetic energy, momentum, the work of the
    // constraints before and after t^n), then 4 per rigid wall (normal impulse, impulse)
    n_part: u32,
    rb_off: u32,
    // 1 when some material erodes (the `ero` array is per element)
    erosion: u32,
    // tied contact: the ties and their offset in par (slave, 4 face nodes, 4 weights)
    n_ties: u32,
    tie_off: u32,
    // element separation: the interfaces (0 without), and where the failure indices start in
    // `ifs` (after the strengths and each group's MODEL and BETA)
    n_if: u32,
    if_index: u32,
    // cohesive laws (0 without): where their `cix` block starts in `ifu`, where its entries and
    // slots start in it, and where the `coh` block starts in `ifs`
    c_ptr: u32,
    c_inc: u32,
    c_slots: u32,
    c_coh: u32,
    // LCTM of *CONTROL_TIMESTEP: the offset of its curve in par (0xffffffff: none)
    dt_max_off: u32,
    pad1: u32,
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
@group(0) @binding(21) var<storage, read> rbi: array<u32>;
@group(0) @binding(22) var<storage, read_write> rb: array<f64>;
@group(0) @binding(23) var<storage, read_write> npe: array<f64>;
@group(0) @binding(24) var<storage, read_write> npn: array<f64>;
@group(0) @binding(25) var<storage, read_write> gps: array<f64>;
@group(0) @binding(26) var<storage, read_write> ero: array<f64>;
@group(0) @binding(27) var<storage, read> eref: array<f64>;
@group(0) @binding(28) var<uniform> prm: Params;
@group(0) @binding(29) var<storage, read> ifu: array<u32>;
@group(0) @binding(30) var<storage, read_write> ifs: array<f64>;
@group(0) @binding(31) var<storage, read_write> ifl: array<atomic<u32>>;

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
const E_FRAC: u32 = 31u;   // the work of the cohesive laws (fracture energy)
const SLOTS: u32 = 25u;   // node entries in use: every node, or the coincident sets' slots
const DT_MID: u32 = 26u;
const W_HALF: u32 = 27u;
const DT_CRIT: u32 = 28u;
const E_ERODED: u32 = 29u;
const N_ERODED: u32 = 30u;
// plain copies of the halt flag (1 once halted) and of "positions due" (1 from the first step
// on: the positions pass moves the nodes at the start of each later step): every thread of
// the per-element and per-node passes reads them, and one atomic load of a single word per
// thread would queue them all on it; only the one-group passes (commit, control, finish) and
// the host write them, between dispatches
const HALTED: u32 = 22u;
const PENDING: u32 = 23u;
// 1 when the step that halted is still to be ended (its time advanced): see advance()
const COMMIT_DUE: u32 = 24u;
const WALL_FORCE: u32 = 32u; // 4 per wall: normal force, force x y z
// (64: the contact energy, contact.wgsl c_energy)
const DT_CONTACT: u32 = 65u; // the contact springs' stable step (BIG without contact)
// cu: control integers
const HALT: u32 = 0u;      // 0 running, 1 output due, 2 finished, 3 error, 4 interfaces failed, 5 elements eroded (with contact), 6 closed cracks released (contact.wgsl)
const ERROR: u32 = 1u;     // 1 inverted element, 2 time step below the floor, 3 bad time step, 4 non-finite
const INVERTED: u32 = 2u;  // lowest inverted element (atomic min)
const NONFINITE: u32 = 3u; // lowest node with a non-finite velocity (atomic min)
const DT_ELEM: u32 = 4u;
const FINISHED: u32 = 6u;
const N_COH: u32 = 5u;     // softening faces in `coh`
const N_CSLOT: u32 = 7u;   // the slots their points join (the list in `cix`)
const ERODED_NOW: u32 = 8u; // 1 when an element eroded in this step (erosion_done)

const MAT_STRIDE: u32 = 14u;
const RB_PAR: u32 = 42u;
const RB_STATE: u32 = 48u;
const NOT_RIGID: u32 = 0xffffffffu;
// emat: the material slot, and the bits of a tetrahedron, of ELFORM 13, of a rigid element
const SLOT: u32 = 0x0fffffffu;
const SRI: u32 = 0x10000000u;
const NP: u32 = 0x20000000u;
const RIGID_EL: u32 = 0x40000000u;
const TET_EL: u32 = 0x80000000u;
const NODE_STRIDE: u32 = 10u;
// Values per rigid wall in par (layout.rs).
const WALL_STRIDE: u32 = 20u;

fn halted() -> bool {
    return cf[HALTED] != 0.0lf;
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

// The integral of curve o from 0 to t (curve.rs Curve::integral: the trapezoids between its
// points, exact for the piecewise-linear curve).
fn curve_integral(o: u32, t: f64) -> f64 {
    var a = 0.0lf;
    var b = t;
    var sign = 1.0lf;
    if (b < a) {
        a = t;
        b = 0.0lf;
        sign = -1.0lf;
    }
    let n = u32(par[o]);
    var s = 0.0lf;
    var prev = a;
    var fprev = curve_eval(o, a);
    for (var i = 0u; i < n; i = i + 1u) {
        let tk = par[o + 1u + i];
        if (tk > a && tk < b) {
            let fk = curve_eval(o, tk);
            s = s + 0.5lf * (fprev + fk) * (tk - prev);
            prev = tk;
            fprev = fk;
        }
    }
    let fb = curve_eval(o, b);
    return sign * (s + 0.5lf * (fprev + fb) * (b - prev));
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

// (written out, with constant indices only: a loop's indices into a local array can send the
// array to memory on a GPU that does not unroll it)
fn mul3(a: M3, b: M3) -> M3 {
    return M3(row_mul3(a[0], b), row_mul3(a[1], b), row_mul3(a[2], b));
}
fn row_mul3(r: vec3<f64>, b: M3) -> vec3<f64> {
    return vec3<f64>(r[0] * b[0][0] + r[1] * b[1][0] + r[2] * b[2][0],
                     r[0] * b[0][1] + r[1] * b[1][1] + r[2] * b[2][1],
                     r[0] * b[0][2] + r[1] * b[1][2] + r[2] * b[2][2]);
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
    // the offset of the material's erosion rule in par, -1 for none
    ero: f64,
}

fn material(m: u32) -> Mat {
    let o = m * MAT_STRIDE;
    return Mat(par[o], par[o + 1u], par[o + 2u], par[o + 3u], par[o + 4u], par[o + 5u],
               par[o + 6u], par[o + 7u], par[o + 8u], par[o + 9u], par[o + 10u], par[o + 11u],
               par[o + 12u], par[o + 13u]);
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

// *MAT_ELASTIC (law 0), *MAT_PLASTIC_KINEMATIC (law 1, radial return with mixed hardening),
// Johnson-Cook (law 2) and *MAT_024 (law 3), over the interval dt.
fn update_material(m: Mat, p: Point, d: S6, dt: f64) -> Point {
    if ((LAWS & 12u) != 0u && m.law > 1.5lf) {
        if ((LAWS & 4u) != 0u && m.law < 2.5lf) {
            return update_johnson_cook(m, p, d, dt);
        }
        var o = p;
        let r = radial_return(m, m.lambda, m.shear, p.sigma, d, p.eps_p, dt, 1.0lf);
        o.sigma = r.sigma;
        if (r.plastic) {
            o.eps_p = p.eps_p + r.x;
        }
        return o;
    }
    var o = p;
    o.sigma = update_elastic(m.lambda, m.shear, p.sigma, d);
    if ((LAWS & 2u) == 0u || m.law < 0.5lf) {
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


// ---------------------------------------------------------------- the other plastic laws
// Material slots of law 2 (Johnson-Cook) and 3 (piecewise linear, *MAT_024) keep their
// parameters in a block of `par` at offset `sigy` (layout.rs).

// The hardening of the curve at par offset o (n, eps_p values, yield stresses) and its slope
// (piecewise.rs hardening_of): interpolated, the last segment's slope past the end, never
// below 0.
fn curve_hardening(o: u32, eps: f64) -> vec2<f64> {
    let n = u32(par[o]);
    if (n == 1u) {
        return vec2<f64>(par[o + 2u], 0.0lf);
    }
    // the number of points with eps_p <= eps, clamped to [1, n - 1]
    var lo = 0u;
    var hi = n;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (par[o + 1u + mid] <= eps) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let k = clamp(lo, 1u, n - 1u);
    let xa = par[o + k];
    let xb = par[o + 1u + k];
    let ya = par[o + n + k];
    let yb = par[o + n + 1u + k];
    let slope = (yb - ya) / (xb - xa);
    return vec2<f64>(max(ya + slope * (eps - xa), 0.0lf), slope);
}

// *MAT_024's flow stress and its slope in the increment x (piecewise.rs update_piecewise).
// Block: C, P, the number of table values (0: one curve), log flag, the curve's offset; with a
// table, then its values and their curves' offsets.
fn flow_piecewise(o: u32, eps_p: f64, x: f64, dt: f64) -> vec2<f64> {
    var rate = 0.0lf;
    var per_dt = 0.0lf;
    if (dt > 0.0lf) {
        rate = x / dt;
        per_dt = 1.0lf / dt;
    }
    let nt = u32(par[o + 2u]);
    if (nt == 0u) {
        let h = curve_hardening(u32(par[o + 4u]), eps_p + x);
        let c = par[o];
        let pp = par[o + 1u];
        var r = 1.0lf;
        var r_slope = 0.0lf;
        if (c > 0.0lf && rate > 0.0lf) {
            let rr = pow64(rate / c, 1.0lf / pp);
            r = 1.0lf + rr;
            r_slope = rr / (pp * rate);
        }
        return vec2<f64>(h.x * r, h.y * r + h.x * r_slope * per_dt);
    }
    // a table of curves by rate (piecewise.rs RateTable::hardening)
    let vo = o + 5u;
    var at = rate;
    var d_at = 1.0lf;
    if (par[o + 3u] > 0.5lf) {
        if (rate > 0.0lf) {
            at = ln64(rate);
            d_at = 1.0lf / rate;
        } else {
            at = -BIG * 2.0lf;
            d_at = 0.0lf;
        }
    }
    if (nt == 1u || at <= par[vo]) {
        return curve_hardening(u32(par[vo + nt]), eps_p + x);
    }
    if (at >= par[vo + nt - 1u]) {
        return curve_hardening(u32(par[vo + 2u * nt - 1u]), eps_p + x);
    }
    var k = 1u;
    while (k < nt - 1u && par[vo + k] <= at) {
        k = k + 1u;
    }
    let w = (at - par[vo + k - 1u]) / (par[vo + k] - par[vo + k - 1u]);
    let a = curve_hardening(u32(par[vo + nt + k - 1u]), eps_p + x);
    let b = curve_hardening(u32(par[vo + nt + k]), eps_p + x);
    let h_rate = (b.x - a.x) / (par[vo + k] - par[vo + k - 1u]) * d_at;
    return vec2<f64>((1.0lf - w) * a.x + w * b.x, (1.0lf - w) * a.y + w * b.y + h_rate * per_dt);
}

// Johnson-Cook (johnson_cook.rs). Block: A, B, N, C, EPSO, M, TM, TR, RO CP, SIGMAX, SIGSAT,
// then the equation of state.
fn jc_rate_factor(o: u32, eps_dot: f64) -> f64 {
    let c = par[o + 3u];
    let eps0 = par[o + 4u];
    if (c == 0.0lf || eps_dot <= eps0) {
        return 1.0lf;
    }
    return 1.0lf + c * ln64(eps_dot / eps0);
}

fn jc_thermal_factor(o: u32, heat: f64) -> f64 {
    let t_melt = par[o + 6u];
    if (!finite(t_melt) || heat <= 0.0lf) {
        return 1.0lf;
    }
    let t_star = min(heat / (t_melt - par[o + 7u]), 1.0lf);
    return 1.0lf - pow64(t_star, par[o + 5u]);
}

fn flow_johnson_cook(o: u32, eps_p: f64, x: f64, dt: f64, theta: f64) -> vec2<f64> {
    let e = eps_p + x;
    let a = par[o];
    let b = par[o + 1u];
    let n = par[o + 2u];
    let sig_max = par[o + 9u];
    var pw = 0.0lf;
    if (e > 0.0lf) {
        pw = pow64(e, n);
    }
    var h = a + b * pw;
    var h_slope = 2.0lf * BIG;
    if (h >= sig_max) {
        h = sig_max;
        h_slope = 0.0lf;
    } else if (e > 0.0lf) {
        h_slope = n * b * pw / e;
    }
    var rate = 0.0lf;
    if (dt > 0.0lf) {
        rate = x / dt;
    }
    let r = jc_rate_factor(o, rate);
    var r_slope = 0.0lf;
    if (r > 1.0lf) {
        r_slope = par[o + 3u] / x;
    }
    let y = h * r * theta;
    let sig_sat = par[o + 10u];
    if (y >= sig_sat) {
        return vec2<f64>(sig_sat, 0.0lf);
    }
    return vec2<f64>(y, (h_slope * r + h * r_slope) * theta);
}

// The flow stress of law 2 or 3 and its slope at the increment x.
fn flow(m: Mat, eps_p: f64, x: f64, dt: f64, theta: f64) -> vec2<f64> {
    let o = u32(m.sigy);
    if (m.law < 2.5lf) {
        return flow_johnson_cook(o, eps_p, x, dt, theta);
    }
    return flow_piecewise(o, eps_p, x, dt);
}

struct Return {
    sigma: S6,
    plastic: bool,
    x: f64,
    y: f64,
}

// The radial return (return_map.rs): the elastic trial, then, where its von Mises value
// exceeds the flow stress, the increment solving q - 3 G x = sigma_y(x) by Newton's method
// kept in its bracket by bisection, and the deviator scaled back to the flow surface.
fn radial_return(m: Mat, lambda: f64, g: f64, sigma: S6, d: S6, eps_p: f64, dt: f64, theta: f64) -> Return {
    var out = Return(update_elastic(lambda, g, sigma, d), false, 0.0lf, 0.0lf);
    let t = out.sigma;
    let pr = (t[0] + t[1] + t[2]) / 3.0lf;
    let sd = S6(t[0] - pr, t[1] - pr, t[2] - pr, t[3], t[4], t[5]);
    let q = sqrt(1.5lf * ddot6(sd, sd));
    if (q <= flow(m, eps_p, 0.0lf, dt, theta).x) {
        return out;
    }
    var lo = 0.0lf;
    var hi = q / (3.0lf * g);
    var x = 0.5lf * hi;
    for (var it = 0; it < 100; it = it + 1) {
        let fy = flow(m, eps_p, x, dt, theta);
        let r = q - 3.0lf * g * x - fy.x;
        if (r > 0.0lf) {
            lo = x;
        } else {
            hi = x;
        }
        if (abs(r) <= 1e-12lf * q || hi - lo <= 1e-15lf * hi) {
            break;
        }
        let newton = x + r / (3.0lf * g + fy.y);
        if (newton > lo && newton < hi) {
            x = newton;
        } else {
            x = 0.5lf * (lo + hi);
        }
    }
    let y = flow(m, eps_p, x, dt, theta).x;
    let sc = y / q;
    out.sigma = S6(pr + sd[0] * sc, pr + sd[1] * sc, pr + sd[2] * sc, sd[3] * sc, sd[4] * sc, sd[5] * sc);
    out.plastic = true;
    out.x = x;
    out.y = y;
    return out;
}

// (A(mu), B(mu)) of the equation of state at par offset o: kind 1 linear polynomial (C0..C6),
// 2 Mie-Gruneisen (C, S1, S2, S3, GAMMA0, A, rho0) (eos.rs coefficients).
fn eos_coefficients(o: u32, mu: f64) -> vec2<f64> {
    if (par[o] < 1.5lf) {
        var c2 = par[o + 3u];
        var c6 = par[o + 7u];
        if (mu < 0.0lf) {
            c2 = 0.0lf;
            c6 = 0.0lf;
        }
        return vec2<f64>(par[o + 1u] + mu * (par[o + 2u] + mu * (c2 + mu * par[o + 4u])),
                         par[o + 5u] + mu * (par[o + 6u] + mu * c6));
    }
    let c = par[o + 1u];
    let gamma0 = par[o + 5u];
    let a = par[o + 6u];
    let k = par[o + 7u] * c * c;
    let b = gamma0 + a * mu;
    if (mu <= 0.0lf) {
        return vec2<f64>(k * mu, b);
    }
    let m1 = mu + 1.0lf;
    let den = 1.0lf - (par[o + 2u] - 1.0lf) * mu - par[o + 3u] * mu * mu / m1 - par[o + 4u] * mu * mu * mu / (m1 * m1);
    let num = k * mu * (1.0lf + (1.0lf - 0.5lf * gamma0) * mu - 0.5lf * a * mu * mu);
    return vec2<f64>(num / (den * den), b);
}

// Johnson-Cook: radial return with the temperature rise of the step's start, the pressure
// from the equation of state if there is one (johnson_cook.rs update_johnson_cook; the
// history's back stress slots hold the temperature rise, ln J and the energy less E0).
fn update_johnson_cook(m: Mat, p: Point, d: S6, dt: f64) -> Point {
    let o = u32(m.sigy);
    var out = p;
    var heat = p.back[0];
    let theta = jc_thermal_factor(o, heat);
    let eos = o + 11u;
    var x = 0.0lf;
    var y = 0.0lf;
    var plastic = false;
    if (par[eos] < 0.5lf) {
        let r = radial_return(m, m.lambda, m.shear, p.sigma, d, p.eps_p, dt, theta);
        out.sigma = r.sigma;
        plastic = r.plastic;
        x = r.x;
        y = r.y;
    } else {
        let s = p.sigma;
        let p_old = -(s[0] + s[1] + s[2]) / 3.0lf;
        let dv = d[0] + d[1] + d[2];
        let dm = dv / 3.0lf;
        let dev = S6(d[0] - dm, d[1] - dm, d[2] - dm, d[3], d[4], d[5]);
        let sm = (s[0] + s[1] + s[2]) / 3.0lf;
        let old = S6(s[0] - sm, s[1] - sm, s[2] - sm, s[3], s[4], s[5]);
        let r = radial_return(m, 0.0lf, m.shear, old, dev, p.eps_p, dt, theta);
        var avg: S6;
        for (var i = 0u; i < 6u; i = i + 1u) {
            avg[i] = 0.5lf * (old[i] + r.sigma[i]);
        }
        let w_dev = ddot6(avg, dev);
        // eos.rs EosState::step
        let e0 = par[eos + 8u];
        let v0 = par[eos + 9u];
        let v_old = v0 * exp64(p.back[1]);
        let ln_j = p.back[1] + dv;
        let v_new = v0 * exp64(ln_j);
        let d_v = v_new - v_old;
        let e_star = e0 + p.back[2] + 0.5lf * (v_old + v_new) * w_dev - 0.5lf * p_old * d_v;
        let ab = eos_coefficients(eos, 1.0lf / v_new - 1.0lf);
        let pn = (ab.x + ab.y * e_star) / (1.0lf + 0.5lf * ab.y * d_v);
        out.back[1] = ln_j;
        out.back[2] = e_star - 0.5lf * pn * d_v - e0;
        let t = r.sigma;
        out.sigma = S6(t[0] - pn, t[1] - pn, t[2] - pn, t[3], t[4], t[5]);
        plastic = r.plastic;
        x = r.x;
        y = r.y;
    }
    if (plastic) {
        let rho_cp = par[o + 8u];
        if (finite(rho_cp)) {
            heat = heat + y * x / rho_cp;
        }
        out.back[0] = heat;
        out.eps_p = p.eps_p + x;
    }
    return out;
}

// ---------------------------------------------------------------- the element pass (kernel.rs)

var<workgroup> r_dt: array<f64, 64>;
var<workgroup> r_id: array<u32, 64>;
var<workgroup> r_ei: array<f64, 64>;
var<workgroup> r_eh: array<f64, 64>;
var<workgroup> r_ee: array<f64, 64>;
var<workgroup> r_en: array<f64, 64>;

// The per-element arrays (connectivity, stress, hourglass forces, corner forces) are stored by
// component, value k of element e at k ne + e: the threads of a group, neighbouring elements,
// read and write neighbouring words (one element's values side by side cost a group a memory
// transaction per thread and value).
fn ek(e: u32, k: u32) -> u32 {
    return k * prm.ne + e;
}

// The positions are kept for two steps: x^n, which the step reads, and x^(n+1), which the
// nodes pass writes with v^(n+1/2), in the halves of xs (3 nn values each) by the parity of
// the step: a step that halts leaves x^n where the host reads it, and no pass of its own
// moves the nodes. Where each half starts is worked out once, first thing in every entry
// point (halves), not at each read.
var<private> x_now: u32;
var<private> x_next: u32;
fn halves() {
    // (the parity taken in f64: exact to 2^53 steps, where a u32 would stop at 2^32)
    let p = u32(cf[STEP] % 2.0lf);
    x_now = p * 3u * prm.nn;
    x_next = (1u - p) * 3u * prm.nn;
}

fn ld(b: u32, n: u32) -> vec3<f64> {
    if (b == 0u) {
        let o = x_now + 3u * n;
        return vec3<f64>(xs[o], xs[o + 1u], xs[o + 2u]);
    }
    return vec3<f64>(vs[3u * n], vs[3u * n + 1u], vs[3u * n + 2u]);
}

struct ElemOut {
    ok: bool,
    dt: f64,
    de_int: f64,
    de_hg: f64,
}

// ---------------------------------------------------------------- erosion (erosion.rs)
// ero per element: eroded (1), its energy so far (the work of its stresses, bulk viscosity and
// hourglass forces), Johnson-Cook damage D and the plastic strain it was last accumulated at.
// A rule at par offset o: FAIL on, FAIL; MXPRES on, MXPRES; MNPRES on, MNPRES; SIGVM on, SIGVM;
// FAILTM on, FAILTM; NCS; the number of *MAT_ADD_EROSION criteria; JC damage on, D1..D5, EFMIN;
// SIGP1, MXEPS, MNEPS, EFFEPS, VOLEPS (each on, value). eref per element: the inverse of its
// reference Jacobian at the centre (9, by rows), when a rule has a strain criterion.

// The eigenvalues of a symmetric tensor, ascending, by cyclic Jacobi rotations (only square
// roots: Vulkan has no 64-bit trigonometry for the CPU's closed form, math.rs
// principal_values; the two agree to round-off but where eigenvalues nearly coincide, where
// the closed form loses digits).
fn eigenvalues(t: S6) -> vec3<f64> {
    var a = M3(vec3<f64>(t[0], t[3], t[5]), vec3<f64>(t[3], t[1], t[4]), vec3<f64>(t[5], t[4], t[2]));
    for (var sweep = 0; sweep < 12; sweep = sweep + 1) {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let dia = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-34lf * dia || off == 0.0lf) {
            break;
        }
        for (var k = 0u; k < 3u; k = k + 1u) {
            let p = select(0u, 1u, k == 2u);
            let q = select(select(1u, 2u, k > 0u), 2u, k == 2u);
            let apq = a[p][q];
            if (apq == 0.0lf) {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0lf * apq);
            var t1 = 1.0lf / (abs(theta) + sqrt(theta * theta + 1.0lf));
            if (abs(theta) > 1e150lf) {
                t1 = 0.5lf / abs(theta);
            }
            if (theta < 0.0lf) {
                t1 = -t1;
            }
            let c = 1.0lf / sqrt(t1 * t1 + 1.0lf);
            let sn = t1 * c;
            let r = 3u - p - q;
            let arp = a[r][p];
            let arq = a[r][q];
            a[p][p] = a[p][p] - t1 * apq;
            a[q][q] = a[q][q] + t1 * apq;
            a[p][q] = 0.0lf;
            a[q][p] = 0.0lf;
            a[r][p] = c * arp - sn * arq;
            a[p][r] = a[r][p];
            a[r][q] = sn * arp + c * arq;
            a[q][r] = a[r][q];
        }
    }
    let d0 = a[0][0];
    let d1 = a[1][1];
    let d2 = a[2][2];
    let lo = min(d0, min(d1, d2));
    let hi = max(d0, max(d1, d2));
    return vec3<f64>(lo, d0 + d1 + d2 - lo - hi, hi);
}

// The principal logarithmic strains of element e, ascending (erosion.rs
// principal_log_strains): F = J(x) J(x0)^-1 at the centre, B = F F^T, 1/2 ln of B's eigenvalues.
fn log_strains(e: u32) -> vec3<f64> {
    var x: P8;
    for (var a = 0u; a < 8u; a = a + 1u) {
        x[a] = ld(0u, conn[ek(e, a)]);
    }
    let o = 9u * e;
    let j0i = M3(vec3<f64>(eref[o], eref[o + 1u], eref[o + 2u]),
                 vec3<f64>(eref[o + 3u], eref[o + 4u], eref[o + 5u]),
                 vec3<f64>(eref[o + 6u], eref[o + 7u], eref[o + 8u]));
    let f = mul3(centre_jacobian(x), j0i);
    let b = mul3(f, transpose3(f));
    let ev = eigenvalues(S6(b[0][0], b[1][1], b[2][2], 0.5lf * (b[0][1] + b[1][0]),
                            0.5lf * (b[1][2] + b[2][1]), 0.5lf * (b[2][0] + b[0][2])));
    let tiny = 2.2250738585072014e-308lf;
    return vec3<f64>(0.5lf * ln64(max(ev[0], tiny)), 0.5lf * ln64(max(ev[1], tiny)), 0.5lf * ln64(max(ev[2], tiny)));
}

fn von_mises6(s: S6) -> f64 {
    let p = (s[0] + s[1] + s[2]) / 3.0lf;
    let d = S6(s[0] - p, s[1] - p, s[2] - p, s[3], s[4], s[5]);
    return sqrt(1.5lf * ddot6(d, d));
}

// Whether the rule at o holds for stress s, plastic strain eps_p at time t (ErosionRule::fails;
// the damage is checked by the caller).
fn rule_fails(o: u32, e: u32, s: S6, eps_p: f64, t: f64) -> bool {
    if (par[o] > 0.5lf && eps_p >= par[o + 1u]) {
        return true;
    }
    if (par[o + 11u] < 0.5lf) {
        return false;
    }
    let p = -(s[0] + s[1] + s[2]) / 3.0lf;
    var held = 0u;
    if (par[o + 2u] > 0.5lf && p >= par[o + 3u]) {
        held = held + 1u;
    }
    if (par[o + 4u] > 0.5lf && p <= par[o + 5u]) {
        held = held + 1u;
    }
    if (par[o + 6u] > 0.5lf && von_mises6(s) >= par[o + 7u]) {
        held = held + 1u;
    }
    if (par[o + 8u] > 0.5lf && t >= par[o + 9u]) {
        held = held + 1u;
    }
    if (par[o + 19u] > 0.5lf && eigenvalues(s)[2] >= par[o + 20u]) {
        held = held + 1u;
    }
    if (par[o + 21u] > 0.5lf || par[o + 23u] > 0.5lf || par[o + 25u] > 0.5lf || par[o + 27u] > 0.5lf) {
        let ls = log_strains(e);
        let vol = ls[0] + ls[1] + ls[2];
        let dv = ls - vec3<f64>(vol / 3.0lf, vol / 3.0lf, vol / 3.0lf);
        let eff = sqrt(2.0lf / 3.0lf * dot(dv, dv));
        if (par[o + 21u] > 0.5lf && ls[2] >= par[o + 22u]) {
            held = held + 1u;
        }
        if (par[o + 23u] > 0.5lf && ls[0] <= par[o + 24u]) {
            held = held + 1u;
        }
        if (par[o + 25u] > 0.5lf && eff >= par[o + 26u]) {
            held = held + 1u;
        }
        let vv = par[o + 28u];
        if (par[o + 27u] > 0.5lf && ((vv > 0.0lf && vol >= vv) || (vv <= 0.0lf && vol <= vv))) {
            held = held + 1u;
        }
    }
    return held >= max(u32(par[o + 10u]), 1u);
}

// The Johnson-Cook failure strain (JcDamage::failure_strain) of the rule at o, for the material
// block jo, at stress s, plastic strain rate eps_dot and temperature rise heat.
fn jc_failure_strain(o: u32, jo: u32, s: S6, eps_dot: f64, heat: f64) -> f64 {
    let vm = von_mises6(s);
    var triax = 0.0lf;
    if (vm > 0.0lf) {
        triax = (s[0] + s[1] + s[2]) / 3.0lf / vm;
    }
    var rate = 0.0lf;
    let eps0 = par[jo + 4u];
    if (eps0 > 0.0lf) {
        rate = ln64(max(eps_dot / eps0, 1.0lf));
    }
    var t_star = 0.0lf;
    let t_melt = par[jo + 6u];
    if (finite(t_melt)) {
        t_star = clamp(heat / (t_melt - par[jo + 7u]), 0.0lf, 1.0lf);
    }
    let f = (par[o + 13u] + par[o + 14u] * exp64(par[o + 15u] * triax)) * (1.0lf + par[o + 16u] * rate) * (1.0lf + par[o + 17u] * t_star);
    return max(f, par[o + 18u]);
}

// After element e's step: its energy, its Johnson-Cook damage, and whether its rule holds now
// (solver/erosion.rs erode_elements). An element that erodes keeps this step's forces; its
// stress, hourglass forces and bulk viscosity are zeroed. Returns the energy it takes away
// (negative when it does not erode).
fn erode(e: u32, m: Mat, work: f64) -> f64 {
    let w = ero[4u * e + 1u] + work;
    ero[4u * e + 1u] = w;
    if (m.ero < 0.0lf) {
        return -1.0lf;
    }
    let o = u32(m.ero);
    let s = S6(sig[ek(e, 0u)], sig[ek(e, 1u)], sig[ek(e, 2u)], sig[ek(e, 3u)], sig[ek(e, 4u)], sig[ek(e, 5u)]);
    let eps_p = hist[7u * e];
    var fails = false;
    if (par[o + 12u] > 0.5lf && m.law > 1.5lf && m.law < 2.5lf) {
        let dep = eps_p - ero[4u * e + 3u];
        if (dep > 0.0lf) {
            let dt = cf[DT_PREV];
            var rate = 0.0lf;
            if (dt > 0.0lf) {
                rate = dep / dt;
            }
            ero[4u * e + 2u] = ero[4u * e + 2u] + dep / jc_failure_strain(o, u32(m.sigy), s, rate, hist[7u * e + 1u]);
            ero[4u * e + 3u] = eps_p;
        }
        fails = ero[4u * e + 2u] >= 1.0lf;
    }
    if (!fails && !rule_fails(o, e, s, eps_p, cf[T])) {
        return -1.0lf;
    }
    ero[4u * e] = 1.0lf;
    atomicStore(&cu[ERODED_NOW], 1u);
    for (var i = 0u; i < 6u; i = i + 1u) {
        sig[ek(e, i)] = 0.0lf;
    }
    for (var i = 0u; i < 12u; i = i + 1u) {
        hgf[ek(e, i)] = 0.0lf;
    }
    bq[e] = 0.0lf;
    return w;
}

struct Stress {
    ok: bool,
    p: Point,
    q: f64,
    eps_v_rate: f64,
    de_int: f64,
}

// Parts 1-4 of the step (kernel.rs update_stress), shared by the shapes: the velocity gradient
// L = J_v J_mid^-1 at the mid-step geometry (J_mid = J_n - dt/2 J_v; the volume is
// vol_per_det det J), the Hughes-Winget rotation, the material update, the internal energy by
// the mid-point rule and the bulk viscosity q with the length l_vol; element e's stress,
// history and q are read and written back.
fn stress_update(e: u32, m: Mat, jn: M3, jv: M3, vol_per_det: f64, l_vol: f64, dt_prev: f64, np: bool, theta_bar: f64) -> Stress {
    var st = Stress(false, Point(S6(0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf), 0.0lf, S6(0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf)), 0.0lf, 0.0lf, 0.0lf);
    var p = Point(S6(sig[ek(e, 0u)], sig[ek(e, 1u)], sig[ek(e, 2u)], sig[ek(e, 3u)], sig[ek(e, 4u)], sig[ek(e, 5u)]),
                  0.0lf, S6(0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf));
    // (a model of elastic parts alone keeps no history: it stays zero)
    if (LAWS != 1u) {
        p.eps_p = hist[7u * e];
        p.back = S6(hist[7u * e + 1u], hist[7u * e + 2u], hist[7u * e + 3u], hist[7u * e + 4u], hist[7u * e + 5u], hist[7u * e + 6u]);
    }
    var de_int = 0.0lf;
    var q = 0.0lf;
    var eps_v_rate = 0.0lf;
    if (dt_prev > 0.0lf) {
        let h = 0.5lf * dt_prev;
        let jm = M3(jn[0] - h * jv[0], jn[1] - h * jv[1], jn[2] - h * jv[2]);
        let detm = det3(jm);
        if (!positive(detm)) {
            return st;
        }
        let jminv = inv3(jm, detm);
        let vol_mid = vol_per_det * detm;
        let l = mul3(jv, jminv);
        var d = S6(l[0][0] * dt_prev, l[1][1] * dt_prev, l[2][2] * dt_prev,
                   0.5lf * (l[0][1] + l[1][0]) * dt_prev, 0.5lf * (l[1][2] + l[2][1]) * dt_prev,
                   0.5lf * (l[2][0] + l[0][2]) * dt_prev);
        if (np) {
            // ELFORM 13: the averaged volumetric increment in place of the element's own
            let shift = (theta_bar - (d[0] + d[1] + d[2])) / 3.0lf;
            d[0] = d[0] + shift;
            d[1] = d[1] + shift;
            d[2] = d[2] + shift;
        }
        let hw = 0.25lf * dt_prev;
        let r = hughes_winget(vec3<f64>(hw * (l[2][1] - l[1][2]), hw * (l[0][2] - l[2][0]), hw * (l[1][0] - l[0][1])));
        p.sigma = rotate_sym(r, p.sigma);
        // (laws 2 and 3 keep scalars in the back stress slots: not turned)
        if (LAWS != 1u && m.law < 1.5lf && (p.back[0] != 0.0lf || p.back[1] != 0.0lf || p.back[2] != 0.0lf || p.back[3] != 0.0lf || p.back[4] != 0.0lf || p.back[5] != 0.0lf)) {
            p.back = rotate_sym(r, p.back);
        }
        let old = p.sigma;
        p = update_material(m, p, d, dt_prev);
        let ns = p.sigma;
        let avg = S6(0.5lf * (old[0] + ns[0]), 0.5lf * (old[1] + ns[1]), 0.5lf * (old[2] + ns[2]),
                     0.5lf * (old[3] + ns[3]), 0.5lf * (old[4] + ns[4]), 0.5lf * (old[5] + ns[5]));
        de_int = vol_mid * ddot6(avg, d);
        eps_v_rate = l[0][0] + l[1][1] + l[2][2];
        if (eps_v_rate < 0.0lf) {
            q = m.density * l_vol * (m.q1 * l_vol * eps_v_rate * eps_v_rate - m.q2 * m.wave_speed * eps_v_rate);
        }
        de_int = de_int - vol_mid * 0.5lf * (bq[e] + q) * eps_v_rate * dt_prev;
    }
    bq[e] = q;
    sig[ek(e, 0u)] = p.sigma[0];
    sig[ek(e, 1u)] = p.sigma[1];
    sig[ek(e, 2u)] = p.sigma[2];
    sig[ek(e, 3u)] = p.sigma[3];
    sig[ek(e, 4u)] = p.sigma[4];
    sig[ek(e, 5u)] = p.sigma[5];
    if (LAWS != 1u) {
        let h = 7u * e;
        hist[h] = p.eps_p;
        hist[h + 1u] = p.back[0];
        hist[h + 2u] = p.back[1];
        hist[h + 3u] = p.back[2];
        hist[h + 4u] = p.back[3];
        hist[h + 5u] = p.back[4];
        hist[h + 6u] = p.back[5];
    }
    st.ok = true;
    st.p = p;
    st.q = q;
    st.eps_v_rate = eps_v_rate;
    st.de_int = de_int;
    return st;
}

// The stable step l_c / (Q + sqrt(Q^2 + c^2)), Q = Q2 c + Q1 l_c |tr L| in compression,
// tr L < -1e-12 c / l_c: a rate of round-off size is none (kernel.rs stable_dt, ROUND_OFF_RATE)
fn stable_dt(lc: f64, c: f64, eps_v_rate: f64, m: Mat) -> f64 {
    var qv = 0.0lf;
    if (eps_v_rate * lc < -1e-12lf * c) {
        qv = m.q2 * c + m.q1 * lc * abs(eps_v_rate);
    }
    return lc / (qv + sqrt(qv * qv + c * c));
}

// The edge matrix J[i][k] = (x_(k+1) - x_0)[i] of a tetrahedron (tet4.rs).
fn edge_matrix(x: array<vec3<f64>, 4>) -> M3 {
    let a = x[1] - x[0];
    let b = x[2] - x[0];
    let c = x[3] - x[0];
    return M3(vec3<f64>(a[0], b[0], c[0]), vec3<f64>(a[1], b[1], c[1]), vec3<f64>(a[2], b[2], c[2]));
}

// The constant-strain tetrahedron (tet4.rs tet4_step) on the corners 0, 1, 2, 4 of its 8-node
// storage; the other four corners get no force, and there is no hourglass control.
fn tet_element(e: u32, m: Mat) -> ElemOut {
    var out = ElemOut(false, BIG, 0.0lf, 0.0lf);
    var x: array<vec3<f64>, 4>;
    var v: array<vec3<f64>, 4>;
    for (var k = 0u; k < 4u; k = k + 1u) {
        let n = conn[ek(e, k + k / 3u)];
        x[k] = ld(0u, n);
        v[k] = ld(1u, n);
    }
    let dt_prev = cf[DT_PREV];
    let jn = edge_matrix(x);
    let detn = det3(jn);
    if (!positive(detn)) {
        return out;
    }
    let jinv = inv3(jn, detn);
    let vol = detn / 6.0lf;
    let l_vol = cbrt64(vol);
    let jv = edge_matrix(v);
    // ELFORM 13 (nodal_pressure.rs): the mean of the 4 nodes' averaged increments
    let np = (emat[e] & NP) != 0u;
    var theta_bar = 0.0lf;
    if (np) {
        for (var k = 0u; k < 4u; k = k + 1u) {
            theta_bar = theta_bar + npn[conn[ek(e, k + k / 3u)]];
        }
        theta_bar = 0.25lf * theta_bar;
    }
    let st = stress_update(e, m, jn, jv, 1.0lf / 6.0lf, l_vol, dt_prev, np, theta_bar);
    if (!st.ok) {
        return out;
    }
    if (np) {
        let sg = st.p.sigma;
        npe[3u * e + 2u] = -(sg[0] + sg[1] + sg[2]) / 3.0lf;
    }
    var b: array<vec3<f64>, 4>;
    b[1] = jinv[0];
    b[2] = jinv[1];
    b[3] = jinv[2];
    b[0] = -(jinv[0] + jinv[1] + jinv[2]);
    let q = st.q;
    let s = S6(st.p.sigma[0] - q, st.p.sigma[1] - q, st.p.sigma[2] - q, st.p.sigma[3], st.p.sigma[4], st.p.sigma[5]);
    var f: P8;
    for (var a = 0u; a < 8u; a = a + 1u) {
        f[a] = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    }
    for (var k = 0u; k < 4u; k = k + 1u) {
        let ba = b[k];
        f[k + k / 3u] = vec3<f64>(-vol * (s[0] * ba[0] + s[3] * ba[1] + s[5] * ba[2]),
                                  -vol * (s[3] * ba[0] + s[1] * ba[1] + s[4] * ba[2]),
                                  -vol * (s[5] * ba[0] + s[4] * ba[1] + s[2] * ba[2]));
    }
    for (var a = 0u; a < 4u; a = a + 1u) {
        for (var i = 0u; i < 3u; i = i + 1u) {
            fe_lo[ek(e, 3u * a + i)] = f[a][i];
            fe_hi[ek(e, 3u * a + i)] = f[a + 4u][i];
        }
    }
    // l_c = 3 V / the largest face area (tet4.rs FACES)
    var c2max = 0.0lf;
    let c0 = cross(x[1] - x[0], x[2] - x[0]);
    let c1 = cross(x[3] - x[0], x[1] - x[0]);
    let c2 = cross(x[3] - x[1], x[2] - x[1]);
    let c3 = cross(x[3] - x[2], x[0] - x[2]);
    c2max = max(max(dot(c0, c0), dot(c1, c1)), max(dot(c2, c2), dot(c3, c3)));
    out.dt = stable_dt(3.0lf * vol / (0.5lf * sqrt(c2max)), m.step_speed, st.eps_v_rate, m);
    out.ok = true;
    out.de_int = st.de_int;
    return out;
}


// The largest squared diagonal cross product of a hexahedron's faces, in hex8.rs FACES order
// (the largest face area is half its root).
fn hex_c2max(x: P8) -> f64 {
    var c2max = 0.0lf;
    c2max = max(c2max, face_c2(x[0], x[3], x[2], x[1]));
    c2max = max(c2max, face_c2(x[4], x[5], x[6], x[7]));
    c2max = max(c2max, face_c2(x[0], x[1], x[5], x[4]));
    c2max = max(c2max, face_c2(x[1], x[2], x[6], x[5]));
    c2max = max(c2max, face_c2(x[2], x[3], x[7], x[6]));
    c2max = max(c2max, face_c2(x[3], x[0], x[4], x[7]));
    return c2max;
}

// ---------------------------------------------------------------- ELFORM 2 (sri.rs)
// gps: per element, its 8 Gauss points' stresses (6), plastic strains and back stresses (or
// Johnson-Cook's scalars) (7): 13 values each.

const GP: f64 = 0.5773502691896258lf;
const GPS_STRIDE: u32 = 104u;

// dN_a/dxi at the natural point p.
fn dn_at(a: u32, p: vec3<f64>) -> vec3<f64> {
    return vec3<f64>(0.125lf * sx(a) * (1.0lf + sy(a) * p[1]) * (1.0lf + sz(a) * p[2]),
                     0.125lf * sy(a) * (1.0lf + sx(a) * p[0]) * (1.0lf + sz(a) * p[2]),
                     0.125lf * sz(a) * (1.0lf + sx(a) * p[0]) * (1.0lf + sy(a) * p[1]));
}

// J[i][k] = sum_a x_a[i] dN_a/dxi_k at p (hex8.rs jacobian_at).
fn jacobian_at(x: P8, p: vec3<f64>) -> M3 {
    var j = M3(vec3<f64>(0.0lf, 0.0lf, 0.0lf), vec3<f64>(0.0lf, 0.0lf, 0.0lf), vec3<f64>(0.0lf, 0.0lf, 0.0lf));
    for (var a = 0u; a < 8u; a = a + 1u) {
        let dn = dn_at(a, p);
        for (var i = 0u; i < 3u; i = i + 1u) {
            j[i] = j[i] + x[a][i] * dn;
        }
    }
    return j;
}

fn gauss_point(g: u32) -> vec3<f64> {
    return vec3<f64>(sx(g) * GP, sy(g) * GP, sz(g) * GP);
}

fn load_point(e: u32, g: u32) -> Point {
    let o = GPS_STRIDE * e + 13u * g;
    return Point(S6(gps[o], gps[o + 1u], gps[o + 2u], gps[o + 3u], gps[o + 4u], gps[o + 5u]),
                 gps[o + 6u],
                 S6(gps[o + 7u], gps[o + 8u], gps[o + 9u], gps[o + 10u], gps[o + 11u], gps[o + 12u]));
}

fn store_point(e: u32, g: u32, p: Point) {
    let o = GPS_STRIDE * e + 13u * g;
    for (var i = 0u; i < 6u; i = i + 1u) {
        gps[o + i] = p.sigma[i];
        gps[o + 7u + i] = p.back[i];
    }
    gps[o + 6u] = p.eps_p;
}

// The fully integrated, selectively reduced hexahedron (sri.rs sri_step): each Gauss point's
// stress updated with the volume-mean volumetric rate, corner forces from the points'
// deviators and the mean pressure, the element's stress the points' volume mean.
fn sri_element(e: u32, m: Mat) -> ElemOut {
    var out = ElemOut(false, BIG, 0.0lf, 0.0lf);
    var x: P8;
    var v: P8;
    for (var a = 0u; a < 8u; a = a + 1u) {
        let n = conn[ek(e, a)];
        x[a] = ld(0u, n);
        v[a] = ld(1u, n);
    }
    var vol_n = 0.0lf;
    for (var g = 0u; g < 8u; g = g + 1u) {
        vol_n = vol_n + det3(jacobian_at(x, gauss_point(g)));
    }
    if (!(vol_n > 0.0lf)) {
        return out;
    }
    let l_vol = cbrt64(vol_n);
    let dt_prev = cf[DT_PREV];
    var de_int = 0.0lf;
    var q = 0.0lf;
    var tr_bar = 0.0lf;
    if (dt_prev > 0.0lf) {
        var xm: P8;
        for (var a = 0u; a < 8u; a = a + 1u) {
            xm[a] = x[a] - (0.5lf * dt_prev) * v[a];
        }
        var ls: array<M3, 8>;
        var ws: array<f64, 8>;
        var num = 0.0lf;
        var den = 0.0lf;
        for (var g = 0u; g < 8u; g = g + 1u) {
            let p = gauss_point(g);
            let jm = jacobian_at(xm, p);
            let w = det3(jm);
            if (!(w > 0.0lf) || !finite(w)) {
                return out;
            }
            let l = mul3(jacobian_at(v, p), inv3(jm, w));
            num = num + w * (l[0][0] + l[1][1] + l[2][2]);
            den = den + w;
            ls[g] = l;
            ws[g] = w;
        }
        tr_bar = num / den;
        for (var g = 0u; g < 8u; g = g + 1u) {
            let l = ls[g];
            let shift = (tr_bar - (l[0][0] + l[1][1] + l[2][2])) / 3.0lf;
            let d = S6((l[0][0] + shift) * dt_prev, (l[1][1] + shift) * dt_prev, (l[2][2] + shift) * dt_prev,
                       0.5lf * (l[0][1] + l[1][0]) * dt_prev, 0.5lf * (l[1][2] + l[2][1]) * dt_prev,
                       0.5lf * (l[2][0] + l[0][2]) * dt_prev);
            let h = 0.25lf * dt_prev;
            let r = hughes_winget(vec3<f64>(h * (l[2][1] - l[1][2]), h * (l[0][2] - l[2][0]), h * (l[1][0] - l[0][1])));
            var pt = load_point(e, g);
            pt.sigma = rotate_sym(r, pt.sigma);
            if (m.law < 1.5lf && (pt.back[0] != 0.0lf || pt.back[1] != 0.0lf || pt.back[2] != 0.0lf || pt.back[3] != 0.0lf || pt.back[4] != 0.0lf || pt.back[5] != 0.0lf)) {
                pt.back = rotate_sym(r, pt.back);
            }
            let old = pt.sigma;
            pt = update_material(m, pt, d, dt_prev);
            var avg: S6;
            for (var i = 0u; i < 6u; i = i + 1u) {
                avg[i] = 0.5lf * (old[i] + pt.sigma[i]);
            }
            de_int = de_int + ws[g] * ddot6(avg, d);
            store_point(e, g, pt);
        }
        if (tr_bar < 0.0lf) {
            q = m.density * l_vol * (m.q1 * l_vol * tr_bar * tr_bar - m.q2 * m.wave_speed * tr_bar);
        }
        de_int = de_int - den * 0.5lf * (bq[e] + q) * tr_bar * dt_prev;
    }
    bq[e] = q;
    // corner forces at x^n (sri.rs corner_forces)
    var f: P8;
    var bbar: P8;
    for (var a = 0u; a < 8u; a = a + 1u) {
        f[a] = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
        bbar[a] = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    }
    var vol = 0.0lf;
    var p_sum = 0.0lf;
    var mean = S6(0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
    var eps_sum = 0.0lf;
    for (var g = 0u; g < 8u; g = g + 1u) {
        let p = gauss_point(g);
        let j = jacobian_at(x, p);
        let w = det3(j);
        if (!positive(w)) {
            return out;
        }
        let jinv = inv3(j, w);
        let pt = load_point(e, g);
        let sg = pt.sigma;
        let pg = -(sg[0] + sg[1] + sg[2]) / 3.0lf;
        let dev = S6(sg[0] + pg, sg[1] + pg, sg[2] + pg, sg[3], sg[4], sg[5]);
        for (var a = 0u; a < 8u; a = a + 1u) {
            let dn = dn_at(a, p);
            let ba = dn[0] * jinv[0] + dn[1] * jinv[1] + dn[2] * jinv[2];
            f[a][0] = f[a][0] - w * (dev[0] * ba[0] + dev[3] * ba[1] + dev[5] * ba[2]);
            f[a][1] = f[a][1] - w * (dev[3] * ba[0] + dev[1] * ba[1] + dev[4] * ba[2]);
            f[a][2] = f[a][2] - w * (dev[5] * ba[0] + dev[4] * ba[1] + dev[2] * ba[2]);
            bbar[a] = bbar[a] + w * ba;
        }
        vol = vol + w;
        p_sum = p_sum + w * pg;
        for (var i = 0u; i < 6u; i = i + 1u) {
            mean[i] = mean[i] + w * sg[i];
        }
        eps_sum = eps_sum + pt.eps_p;
    }
    let p_bar = p_sum / vol;
    for (var a = 0u; a < 8u; a = a + 1u) {
        f[a] = f[a] + (p_bar + q) * bbar[a];
    }
    for (var i = 0u; i < 6u; i = i + 1u) {
        sig[ek(e, i)] = mean[i] / vol;
        hist[7u * e + 1u + i] = 0.0lf;
    }
    // the element's history for output: the points' mean plastic strain
    hist[7u * e] = eps_sum / 8.0lf;
    for (var a = 0u; a < 4u; a = a + 1u) {
        for (var i = 0u; i < 3u; i = i + 1u) {
            fe_lo[ek(e, 3u * a + i)] = f[a][i];
            fe_hi[ek(e, 3u * a + i)] = f[a + 4u][i];
        }
    }
    out.dt = stable_dt(vol_n / (0.5lf * sqrt(hex_c2max(x))), m.step_speed, tr_bar, m);
    out.ok = true;
    out.de_int = de_int;
    return out;
}

fn element(e: u32) -> ElemOut {
    if (HAS_RIGID && (emat[e] & RIGID_EL) != 0u) {
        // an element of a rigid part: it moves with its body, no stress, no step limit. Its
        // corner forces are zeroed each step: ELFORM 13's pressure correction adds to them
        // (a rigid tetrahedron takes part in the averages, as on the CPU)
        for (var i = 0u; i < 12u; i = i + 1u) {
            fe_lo[ek(e, i)] = 0.0lf;
            fe_hi[ek(e, i)] = 0.0lf;
        }
        return ElemOut(true, BIG, 0.0lf, 0.0lf);
    }
    let m = material(emat[e] & SLOT);
    if (HAS_TET && (emat[e] & TET_EL) != 0u) {
        return tet_element(e, m);
    }
    if (HAS_SRI && (emat[e] & SRI) != 0u) {
        return sri_element(e, m);
    }
    return hex_element(e, m);
}

// ---------------------------------------------------------------- the one-point hexahedron
// hex8.rs, also on a wedge's degenerate corners (shape.rs). Written for registers: the corners
// are read into values indexed only by constants, the hourglass rates are taken before the
// stress update, the corners' positions are read again after it for the corner forces (J^-1
// and gx formed again: kept across the update they cost 8% of the step on an H100), and b_a
// and gamma_a are formed again, corner by corner, where they are used (the same operations in
// the same order as kernel.rs, so the same bits), so that no per-corner array outlives its use.

alias Q4 = array<vec3<f64>, 4>;

// b_a = 1/8 (s_a J^-T) at the centre, from the rows of J^-1.
fn hex_b(a: u32, jinv: M3) -> vec3<f64> {
    return 0.125lf * (sx(a) * jinv[0] + sy(a) * jinv[1] + sz(a) * jinv[2]);
}

// gx_al = sum_a Gamma_al,a x_a (each Gamma is +-1: the sums are exact in any grouping but
// are kept in corner order).
fn hex_gx(x: P8) -> Q4 {
    return Q4(hex_gx_mode(0u, x), hex_gx_mode(1u, x), hex_gx_mode(2u, x), hex_gx_mode(3u, x));
}
fn hex_gx_mode(al: u32, x: P8) -> vec3<f64> {
    return gamma_base(al, 0u) * x[0] + gamma_base(al, 1u) * x[1] + gamma_base(al, 2u) * x[2]
        + gamma_base(al, 3u) * x[3] + gamma_base(al, 4u) * x[4] + gamma_base(al, 5u) * x[5]
        + gamma_base(al, 6u) * x[6] + gamma_base(al, 7u) * x[7];
}

// Corner a's hourglass shape vectors gamma_al,a = Gamma_al,a - gx_al . b_a (Flanagan-Belytschko).
fn hex_gamma(a: u32, b: vec3<f64>, gx: Q4) -> vec4<f64> {
    return vec4<f64>(gamma_base(0u, a) - (gx[0][0] * b[0] + gx[0][1] * b[1] + gx[0][2] * b[2]),
                     gamma_base(1u, a) - (gx[1][0] * b[0] + gx[1][1] * b[1] + gx[1][2] * b[2]),
                     gamma_base(2u, a) - (gx[2][0] * b[0] + gx[2][1] * b[1] + gx[2][2] * b[2]),
                     gamma_base(3u, a) - (gx[3][0] * b[0] + gx[3][1] * b[1] + gx[3][2] * b[2]));
}

// Corner a's share of sum_a |b_a|^2 and of the hourglass rates qd_al += v_a gamma_al,a.
struct Rates {
    bb: f64,
    qd: Q4,
}
fn hex_rate(r: Rates, a: u32, v: vec3<f64>, jinv: M3, gx: Q4) -> Rates {
    let b = hex_b(a, jinv);
    let g = hex_gamma(a, b, gx);
    return Rates(r.bb + (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]),
                 Q4(r.qd[0] + v * g[0], r.qd[1] + v * g[1], r.qd[2] + v * g[2], r.qd[3] + v * g[3]));
}

// Mode al's hourglass force from its rate (viscous: coef qd; stiffness: old + coef qd), stored
// as element e's values 3 al .. 3 al + 2 of hgf; its energy increment 1/2 (old + new) qd dt is
// added to de in component order.
struct Mode {
    f: vec3<f64>,
    de: f64,
}
fn hex_mode(e: u32, al: u32, qd: vec3<f64>, coef: f64, stiff: bool, dt_prev: f64, de: f64) -> Mode {
    let k = 3u * al;
    let old = vec3<f64>(hgf[ek(e, k)], hgf[ek(e, k + 1u)], hgf[ek(e, k + 2u)]);
    var f = coef * qd;
    if (stiff) {
        f = old + coef * qd;
    }
    hgf[ek(e, k)] = f[0];
    hgf[ek(e, k + 1u)] = f[1];
    hgf[ek(e, k + 2u)] = f[2];
    var d = de + 0.5lf * (old[0] + f[0]) * qd[0] * dt_prev;
    d = d + 0.5lf * (old[1] + f[1]) * qd[1] * dt_prev;
    d = d + 0.5lf * (old[2] + f[2]) * qd[2] * dt_prev;
    return Mode(f, d);
}

// Corner a's force f_a = -V (sigma - q I) b_a - sum_al f_hg,al gamma_al,a, stored.
fn hex_corner(e: u32, a: u32, vol: f64, s: S6, fhg: Q4, jinv: M3, gx: Q4) {
    let ba = hex_b(a, jinv);
    let g = hex_gamma(a, ba, gx);
    var f = vec3<f64>(-vol * (s[0] * ba[0] + s[3] * ba[1] + s[5] * ba[2]),
                      -vol * (s[3] * ba[0] + s[1] * ba[1] + s[4] * ba[2]),
                      -vol * (s[5] * ba[0] + s[4] * ba[1] + s[2] * ba[2]));
    f = f - fhg[0] * g[0];
    f = f - fhg[1] * g[1];
    f = f - fhg[2] * g[2];
    f = f - fhg[3] * g[3];
    let k = 3u * (a & 3u);
    if (a < 4u) {
        fe_lo[ek(e, k)] = f[0];
        fe_lo[ek(e, k + 1u)] = f[1];
        fe_lo[ek(e, k + 2u)] = f[2];
    } else {
        fe_hi[ek(e, k)] = f[0];
        fe_hi[ek(e, k + 1u)] = f[1];
        fe_hi[ek(e, k + 2u)] = f[2];
    }
}

fn hex_element(e: u32, m: Mat) -> ElemOut {
    var out = ElemOut(false, BIG, 0.0lf, 0.0lf);
    let dt_prev = cf[DT_PREV];
    let stiff = m.hg > 0.5lf;
    // 6a and 1-4: the hourglass rates and the stress update, from the corners read once
    let h = hex_kinematics(e, m, dt_prev);
    if (!h.ok) {
        return out;
    }
    let st = h.st;
    let r = h.r;
    let vol = h.vol;
    let l_vol = h.l_vol;

    // 6b: the hourglass forces, viscous or stiffness
    var coef: f64;
    if (stiff) {
        coef = m.qh * (m.lambda + 2.0lf * m.shear) * vol * r.bb / 8.0lf * dt_prev;
    } else {
        coef = m.qh * m.density * m.wave_speed * l_vol * l_vol / 4.0lf;
    }
    let m0 = hex_mode(e, 0u, r.qd[0], coef, stiff, dt_prev, 0.0lf);
    let m1 = hex_mode(e, 1u, r.qd[1], coef, stiff, dt_prev, m0.de);
    let m2 = hex_mode(e, 2u, r.qd[2], coef, stiff, dt_prev, m1.de);
    let m3 = hex_mode(e, 3u, r.qd[3], coef, stiff, dt_prev, m2.de);
    let fhg = Q4(m0.f, m1.f, m2.f, m3.f);

    // 5: corner forces, from the corners read again (J^-1 and gx formed again from them, the
    // same operations on the same values: the same bits), so that neither is held in
    // registers across the stress update
    let x = P8(ld(0u, conn[ek(e, 0u)]), ld(0u, conn[ek(e, 1u)]), ld(0u, conn[ek(e, 2u)]), ld(0u, conn[ek(e, 3u)]),
               ld(0u, conn[ek(e, 4u)]), ld(0u, conn[ek(e, 5u)]), ld(0u, conn[ek(e, 6u)]), ld(0u, conn[ek(e, 7u)]));
    let jn = centre_jacobian(x);
    let jinv = inv3(jn, det3(jn));
    let gx = hex_gx(x);
    let p = st.p;
    let q = st.q;
    let s = S6(p.sigma[0] - q, p.sigma[1] - q, p.sigma[2] - q, p.sigma[3], p.sigma[4], p.sigma[5]);
    hex_corner(e, 0u, vol, s, fhg, jinv, gx);
    hex_corner(e, 1u, vol, s, fhg, jinv, gx);
    hex_corner(e, 2u, vol, s, fhg, jinv, gx);
    hex_corner(e, 3u, vol, s, fhg, jinv, gx);
    hex_corner(e, 4u, vol, s, fhg, jinv, gx);
    hex_corner(e, 5u, vol, s, fhg, jinv, gx);
    hex_corner(e, 6u, vol, s, fhg, jinv, gx);
    hex_corner(e, 7u, vol, s, fhg, jinv, gx);

    // 7: stable time step l_c / (Q + sqrt(Q^2 + c^2)), l_c = V / largest face area
    out.dt = stable_dt(vol / (0.5lf * sqrt(h.c2max)), m.step_speed, st.eps_v_rate, m);
    out.ok = true;
    out.de_int = st.de_int;
    out.de_hg = m3.de;
    return out;
}

// What the hexahedron's first parts leave for its forces: the hourglass rates, the updated
// stress, the volume, its cube root and the largest face's squared doubled area.
struct HexKin {
    ok: bool,
    st: Stress,
    r: Rates,
    vol: f64,
    l_vol: f64,
    c2max: f64,
}

fn hex_kinematics(e: u32, m: Mat, dt_prev: f64) -> HexKin {
    // (a var starts at zero: not ok)
    var out: HexKin;
    let n = array<u32, 8>(conn[ek(e, 0u)], conn[ek(e, 1u)], conn[ek(e, 2u)], conn[ek(e, 3u)], conn[ek(e, 4u)],
                          conn[ek(e, 5u)], conn[ek(e, 6u)], conn[ek(e, 7u)]);
    let x = P8(ld(0u, n[0]), ld(0u, n[1]), ld(0u, n[2]), ld(0u, n[3]), ld(0u, n[4]),
               ld(0u, n[5]), ld(0u, n[6]), ld(0u, n[7]));
    let v = P8(ld(1u, n[0]), ld(1u, n[1]), ld(1u, n[2]), ld(1u, n[3]), ld(1u, n[4]),
               ld(1u, n[5]), ld(1u, n[6]), ld(1u, n[7]));
    let jn = centre_jacobian(x);
    let detn = det3(jn);
    if (!positive(detn)) {
        return out;
    }
    let jinv = inv3(jn, detn);
    out.vol = 8.0lf * detn;
    out.l_vol = cbrt64(out.vol);
    let jv = centre_jacobian(v);
    out.c2max = hex_c2max(x);
    let gx = hex_gx(x);

    // 6a: the hourglass rates qd_al = sum_a v_a gamma_al,a (and sum_a |b_a|^2 for the
    // stiffness form), before the stress update so that x and v die here
    var r: Rates;
    r = hex_rate(r, 0u, v[0], jinv, gx);
    r = hex_rate(r, 1u, v[1], jinv, gx);
    r = hex_rate(r, 2u, v[2], jinv, gx);
    r = hex_rate(r, 3u, v[3], jinv, gx);
    r = hex_rate(r, 4u, v[4], jinv, gx);
    r = hex_rate(r, 5u, v[5], jinv, gx);
    r = hex_rate(r, 6u, v[6], jinv, gx);
    r = hex_rate(r, 7u, v[7], jinv, gx);
    out.r = r;

    // 1-4: stress update over the previous interval
    out.st = stress_update(e, m, jn, jv, 8.0lf, out.l_vol, dt_prev, false, 0.0lf);
    out.ok = out.st.ok;
    return out;
}

@compute @workgroup_size(64)
fn elements(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
            @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let grp = wid.y * nw.x + wid.x;
    let e = 64u * grp + lid.x;
    let run = !halted();
    var dt = BIG;
    var id = 0xffffffffu;
    var ei = 0.0lf;
    var eh = 0.0lf;
    var ee = 0.0lf;
    var en = 0.0lf;
    if (run && e < prm.ne) {
        if (HAS_EROSION && prm.erosion != 0u && ero[4u * e] != 0.0lf) {
            // eroded: no force, no time step
            for (var i = 0u; i < 12u; i = i + 1u) {
                fe_lo[ek(e, i)] = 0.0lf;
                fe_hi[ek(e, i)] = 0.0lf;
            }
        } else {
            let r = element(e);
            if (r.ok) {
                dt = r.dt;
                id = e;
                ei = r.de_int;
                eh = r.de_hg;
                if (HAS_EROSION && prm.erosion != 0u && (emat[e] & RIGID_EL) == 0u) {
                    let gone = erode(e, material(emat[e] & SLOT), r.de_int + r.de_hg);
                    if (gone >= 0.0lf) {
                        ee = gone;
                        en = 1.0lf;
                    }
                }
            } else {
                atomicMin(&cu[INVERTED], e);
            }
        }
    }
    let l = lid.x;
    r_dt[l] = dt;
    r_id[l] = id;
    r_ei[l] = ei;
    r_eh[l] = eh;
    r_ee[l] = ee;
    r_en[l] = en;
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
            r_ee[l] = r_ee[l] + r_ee[o];
            r_en[l] = r_en[l] + r_en[o];
        }
        workgroupBarrier();
    }
    if (l == 0u && run && grp < prm.groups_e) {
        let g = grp;
        let gs = prm.groups_e;
        epart[g] = r_dt[0];
        epart[gs + g] = f64(r_id[0]);
        epart[2u * gs + g] = r_ei[0];
        epart[3u * gs + g] = r_eh[0];
        epart[4u * gs + g] = r_ee[0];
        epart[5u * gs + g] = r_en[0];
    }
}



// ---------------------------------------------------------------- ELFORM 13 (nodal_pressure.rs)
// npe per element: the mid-step volume V (the weight; 0 for other elements and for one flat at
// mid-step), its own volumetric increment theta, its pressure p after the update; npn per
// node: the weighted mean of theta, then of p, over its ELFORM 13 elements.

// The corners 0, 1, 2, 4 of a tetrahedron's 8-node storage.
fn tet_nodes(e: u32) -> array<u32, 4> {
    return array<u32, 4>(conn[ek(e, 0u)], conn[ek(e, 1u)], conn[ek(e, 2u)], conn[ek(e, 4u)]);
}

@compute @workgroup_size(64)
fn np_theta(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
            @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let e = 64u * (wid.y * nw.x + wid.x) + lid.x;
    if (e >= prm.ne || halted() || (emat[e] & NP) == 0u) {
        return;
    }
    if (HAS_EROSION && prm.erosion != 0u && ero[4u * e] != 0.0lf) {
        // an eroded tetrahedron leaves the averages
        npe[3u * e] = 0.0lf;
        npe[3u * e + 1u] = 0.0lf;
        return;
    }
    let ns = tet_nodes(e);
    var x: array<vec3<f64>, 4>;
    var v: array<vec3<f64>, 4>;
    for (var k = 0u; k < 4u; k = k + 1u) {
        x[k] = ld(0u, ns[k]);
        v[k] = ld(1u, ns[k]);
    }
    // tet4.rs volume_increment
    let dt = cf[DT_PREV];
    let jn = edge_matrix(x);
    let jv = edge_matrix(v);
    let h = 0.5lf * dt;
    let jm = M3(jn[0] - h * jv[0], jn[1] - h * jv[1], jn[2] - h * jv[2]);
    let d = det3(jm);
    var w = 0.0lf;
    var th = 0.0lf;
    if (positive(d)) {
        let l = mul3(jv, inv3(jm, d));
        w = d / 6.0lf;
        th = (l[0][0] + l[1][1] + l[2][2]) * dt;
    }
    npe[3u * e] = w;
    npe[3u * e + 1u] = th;
}

// npn[n] = sum_e V_e val_e / sum_e V_e over the node's elements (value k of npe: 1 theta,
// 2 pressure), in element order.
fn np_node(n: u32, k: u32) {
    var num = 0.0lf;
    var den = 0.0lf;
    for (var i = nptr[2u * n]; i < nptr[2u * n + 1u]; i = i + 1u) {
        let e = ninc[i] >> 3u;
        let a = ninc[i] & 7u;
        // a tetrahedron's node once, at its corner 0, 1, 2 or 4
        if ((emat[e] & NP) == 0u || a == 3u || a > 4u) {
            continue;
        }
        num = num + npe[3u * e] * npe[3u * e + k];
        den = den + npe[3u * e];
    }
    var val = 0.0lf;
    if (den > 0.0lf) {
        val = num / den;
    }
    npn[n] = val;
}

@compute @workgroup_size(64)
fn np_node_theta(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
                 @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let n = 64u * (wid.y * nw.x + wid.x) + lid.x;
    if (n < prm.nn && !halted()) {
        np_node(n, 1u);
    }
}

@compute @workgroup_size(64)
fn np_node_p(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
             @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let n = 64u * (wid.y * nw.x + wid.x) + lid.x;
    if (n < prm.nn && !halted()) {
        np_node(n, 2u);
    }
}

// The pressure correction V^n (p_tilde - p_e) b_a of each ELFORM 13 element's corner forces,
// p_tilde the mean of its 4 nodes' averaged pressures (nodal_pressure.rs correct_forces).
@compute @workgroup_size(64)
fn np_correct(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
              @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let e = 64u * (wid.y * nw.x + wid.x) + lid.x;
    if (e >= prm.ne || halted() || (emat[e] & NP) == 0u || npe[3u * e] == 0.0lf) {
        return;
    }
    let ns = tet_nodes(e);
    var x: array<vec3<f64>, 4>;
    var pt = 0.0lf;
    for (var k = 0u; k < 4u; k = k + 1u) {
        x[k] = ld(0u, ns[k]);
        pt = pt + npn[ns[k]];
    }
    pt = 0.25lf * pt;
    let jn = edge_matrix(x);
    let d = det3(jn);
    if (!positive(d)) {
        return;
    }
    let jinv = inv3(jn, d);
    let vol = d / 6.0lf;
    let c = vol * (pt - npe[3u * e + 2u]);
    var b: array<vec3<f64>, 4>;
    b[1] = jinv[0];
    b[2] = jinv[1];
    b[3] = jinv[2];
    b[0] = -(jinv[0] + jinv[1] + jinv[2]);
    for (var k = 0u; k < 4u; k = k + 1u) {
        let a = k + k / 3u;
        for (var i = 0u; i < 3u; i = i + 1u) {
            let f = c * b[k][i];
            if (a < 4u) {
                fe_lo[ek(e, 3u * a + i)] = fe_lo[ek(e, 3u * a + i)] + f;
            } else {
                fe_hi[ek(e, 3u * (a - 4u) + i)] = fe_hi[ek(e, 3u * (a - 4u) + i)] + f;
            }
        }
    }
}

// ---------------------------------------------------------------- rigid bodies (rigid.rs)

fn rb_vec(o: u32) -> vec3<f64> {
    return vec3<f64>(rb[o], rb[o + 1u], rb[o + 2u]);
}

fn rb_mat(o: u32) -> M3 {
    return M3(rb_vec(o), rb_vec(o + 3u), rb_vec(o + 6u));
}

fn rb_set_vec(o: u32, v: vec3<f64>) {
    rb[o] = v[0];
    rb[o + 1u] = v[1];
    rb[o + 2u] = v[2];
}

fn rb_set_mat(o: u32, a: M3) {
    rb_set_vec(o, a[0]);
    rb_set_vec(o + 3u, a[1]);
    rb_set_vec(o + 6u, a[2]);
}

fn mat_vec3(a: M3, v: vec3<f64>) -> vec3<f64> {
    return vec3<f64>(dot(a[0], v), dot(a[1], v), dot(a[2], v));
}

// The spatial inertia R I0 R^T of body block bo.
fn rb_inertia(bo: u32, r: M3) -> M3 {
    let i0 = M3(vec3<f64>(par[bo + 4u], par[bo + 5u], par[bo + 6u]),
                vec3<f64>(par[bo + 7u], par[bo + 8u], par[bo + 9u]),
                vec3<f64>(par[bo + 10u], par[bo + 11u], par[bo + 12u]));
    return mul3(mul3(r, i0), transpose3(r));
}

var<workgroup> rb_s: array<f64, 64>;

// The arm of body block bo's unlumped mass from its reference centre of mass.
fn rb_arm(bo: u32) -> vec3<f64> {
    return vec3<f64>(par[bo + 24u], par[bo + 25u], par[bo + 26u]);
}

// (a - b) / h, entry by entry.
fn rate3(a: M3, b: M3, h: f64) -> M3 {
    return M3((a[0] - b[0]) / h, (a[1] - b[1]) / h, (a[2] - b[2]) / h);
}

// The unlumped mass of body b (a given inertia; none: zeros): its share of the leapfrog's
// kinetic energy at t^n and its momentum at t^(n-1/2), from the placements at t^(n-1), t^n
// and t^(n+1) (rigid.rs RigidBody::unlumped_motion): `1/2 M c'^- . c'^+ + 1/2 tr(R'^- J
// R'^+^T)`, the rates the differences of the placements over their steps; at the first step
// the rate before t^0 is `2 r'^0 - r'^+`, r'^0 from the initial velocities. Read by the
// finish pass (its control block in workgroup memory), after the rigid pass placed the next
// step.
struct Unlumped {
    ke: f64,
    p: vec3<f64>,
}
fn rb_unlumped(b: u32) -> Unlumped {
    let bo = prm.rb_off + RB_PAR * b;
    let so = RB_STATE * b;
    let m = par[bo + 23u];
    let dt = wcf[DT];
    var out = Unlumped(0.0lf, vec3<f64>(0.0lf, 0.0lf, 0.0lf));
    if (m == 0.0lf || dt <= 0.0lf) {
        return out;
    }
    let arm = rb_arm(bo);
    let j = M3(vec3<f64>(par[bo + 27u], par[bo + 28u], par[bo + 29u]),
               vec3<f64>(par[bo + 30u], par[bo + 31u], par[bo + 32u]),
               vec3<f64>(par[bo + 33u], par[bo + 34u], par[bo + 35u]));
    let r0 = rb_mat(so + 6u);
    let r1 = rb_mat(so + 24u);
    let c0 = rb_vec(so) + mat_vec3(r0, arm);
    let c_new = (rb_vec(so + 21u) + mat_vec3(r1, arm) - c0) * (1.0lf / dt);
    let a_new = rate3(r1, r0, dt);
    var c_old = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    var a_old = r0;
    let dp = wcf[DT_PREV];
    if (wcf[STEP] == 0.0lf || dp <= 0.0lf) {
        let v0 = vec3<f64>(par[bo + 36u], par[bo + 37u], par[bo + 38u]);
        let w0 = vec3<f64>(par[bo + 39u], par[bo + 40u], par[bo + 41u]);
        let c_init = v0 + cross(w0, mat_vec3(r0, arm));
        let w = M3(vec3<f64>(0.0lf, -w0[2], w0[1]), vec3<f64>(w0[2], 0.0lf, -w0[0]),
                   vec3<f64>(-w0[1], w0[0], 0.0lf));
        let a_init = mul3(w, r0);
        c_old = c_init * 2.0lf - c_new;
        for (var i = 0u; i < 3u; i = i + 1u) {
            a_old[i] = a_init[i] * 2.0lf - a_new[i];
        }
    } else {
        let cp = rb_vec(so + 36u) + mat_vec3(rb_mat(so + 39u), arm);
        c_old = (c0 - cp) * (1.0lf / dp);
        a_old = rate3(r0, rb_mat(so + 39u), dp);
    }
    // tr(A J B^T) = sum over i, k of (A J)_ik B_ik
    let aj = mul3(a_old, j);
    var tr = 0.0lf;
    for (var i = 0u; i < 3u; i = i + 1u) {
        for (var k = 0u; k < 3u; k = k + 1u) {
            tr = tr + aj[i][k] * a_new[i][k];
        }
    }
    out.ke = 0.5lf * m * dot(c_old, c_new) + 0.5lf * tr;
    out.p = c_old * m;
    return out;
}

// The sum of `val` over the 64 threads of the group, by a tree of fixed shape.
fn rb_sum(l: u32, val: f64) -> f64 {
    rb_s[l] = val;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s = s >> 1u) {
        if (l < s) {
            rb_s[l] = rb_s[l] + rb_s[l + s];
        }
        workgroupBarrier();
    }
    let total = rb_s[0];
    workgroupBarrier();
    return total;
}

// One group per body: the force and moment about the centre of mass summed over its nodes (in
// a fixed order), v_cm += F/M dt, the angular momentum and velocity by the implicit mid-point
// rule, the constraints and prescribed motions, their work, and the placement of the next step
// (solver.rs update_rigid_bodies, rigid.rs update_angular).
@compute @workgroup_size(64)
fn rigid(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
         @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let b = wid.y * nw.x + wid.x;
    let l = lid.x;
    let live = !halted() && b < prm.n_rigid;
    var bo = 0u;
    var so = 0u;
    var fs = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    var ms = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    if (live) {
        bo = prm.rb_off + RB_PAR * b;
        so = RB_STATE * b;
        let x_cm = rb_vec(so);
        let first = u32(par[bo + 21u]);
        let count = u32(par[bo + 22u]);
        let list = prm.nn + first;
        let t = cf[T];
        for (var k = l; k < count; k = k + 64u) {
            let n = rbi[list + k];
            let f = node_force(n) + node_loads(n, t) + contact_force(n);
            fs = fs + f;
            ms = ms + cross(ld(0u, n) - x_cm, f);
        }
    }
    var tot: array<f64, 6>;
    for (var i = 0u; i < 3u; i = i + 1u) {
        tot[i] = rb_sum(l, fs[i]);
        tot[3u + i] = rb_sum(l, ms[i]);
    }
    if (!live || l != 0u) {
        return;
    }
    var force = vec3<f64>(tot[0], tot[1], tot[2]);
    var moment = vec3<f64>(tot[3], tot[4], tot[5]);
    // the body loads on the mass no node carries (a given inertia), at its centre
    let m_u = par[bo + 23u];
    if (m_u != 0.0lf) {
        let x_c = rb_vec(so);
        let c = x_c + mat_vec3(rb_mat(so + 6u), rb_arm(bo));
        let fu = vec3<f64>(cf[G_NOW], cf[G_NOW + 1u], cf[G_NOW + 2u]) * m_u;
        force = fu + force;
        moment = cross(c - x_c, fu) + moment;
    }
    let dt_mid = cf[DT_MID];
    let dt = cf[DT];
    let mass_b = par[bo];
    let rot = rb_mat(so + 6u);
    let v_old = rb_vec(so + 3u);
    let w_old = rb_vec(so + 18u);
    var v_cm = v_old + force * (dt_mid / mass_b);
    // update_angular
    let ang = rb_vec(so + 15u) + moment * dt_mid;
    var ang_mom = ang;
    let inertia = rb_inertia(bo, rot);
    let d = det3(inertia);
    var omega = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    if (d != 0.0lf && finite(d)) {
        let inv = inv3(inertia, d);
        omega = mat_vec3(inv, ang);
        for (var it = 0; it < 50; it = it + 1) {
            let q = hughes_winget(omega * (0.5lf * dt));
            let next = mat_vec3(inv, (ang + mat_vec3(transpose3(q), ang)) * 0.5lf);
            let dn = next - omega;
            let change = sqrt(dot(dn, dn));
            omega = next;
            if (change <= 1e-15lf * sqrt(dot(omega, omega))) {
                break;
            }
        }
    }
    let v_free = v_cm;
    let w_free = omega;
    // apply_constraints
    for (var i = 0u; i < 3u; i = i + 1u) {
        if (par[bo + 13u + i] > 0.5lf) {
            v_cm[i] = 0.0lf;
        }
    }
    if (par[bo + 16u] > 0.5lf || par[bo + 17u] > 0.5lf || par[bo + 18u] > 0.5lf) {
        for (var i = 0u; i < 3u; i = i + 1u) {
            if (par[bo + 16u + i] > 0.5lf) {
                omega[i] = 0.0lf;
            }
        }
        ang_mom = mat_vec3(inertia, omega);
    }
    // prescribed motions, in the deck's order
    let x_cm = rb_vec(so);
    let t = cf[T];
    let mo = u32(par[bo + 19u]);
    for (var k = 0u; k < u32(par[bo + 20u]); k = k + 1u) {
        // code 0-2: a global axis; 3: along the unit vector d; 4: a rotation about d; with
        // `only` the components normal to d are held (model.rs MotionDof::apply)
        let o = mo + 10u * k;
        let tm = t + 0.5lf * dt;
        if (tm < par[o + 8u] || tm >= par[o + 9u]) {
            continue;
        }
        let code = u32(par[o]);
        let c = u32(par[o + 3u]);
        let d = vec3<f64>(par[o + 4u], par[o + 5u], par[o + 6u]);
        let only = par[o + 7u] > 0.5lf;
        if (code == 4u) {
            let s = par[o + 2u] * curve_eval(c, t + 0.5lf * dt);
            if (only) {
                omega = d * s;
            } else {
                omega = omega + d * (s - dot(omega, d));
            }
            ang_mom = mat_vec3(inertia, omega);
            continue;
        }
        let axis = select(code, 0u, code == 3u);
        let x_cm0 = vec3<f64>(par[bo + 1u], par[bo + 2u], par[bo + 3u]);
        var s = 0.0lf;
        if (par[o + 1u] < 0.5lf) {
            s = par[o + 2u] * curve_eval(c, t + 0.5lf * dt);
        } else {
            let goal = select(x_cm0[axis], dot(x_cm0, d), code == 3u)
                + par[o + 2u] * curve_eval(c, t + dt);
            s = (goal - select(x_cm[axis], dot(x_cm, d), code == 3u)) / dt;
        }
        if (code < 3u) {
            v_cm[axis] = s;
        } else if (only) {
            v_cm = d * s;
        } else {
            v_cm = v_cm + d * (s - dot(v_cm, d));
        }
    }
    // the work of the constraint reactions: impulse . mean velocity
    let dp = (v_cm - v_free) * mass_b;
    let dl = mat_vec3(inertia, omega - w_free);
    rb[so + 33u] = 0.5lf * (dot(dp, v_old) + dot(dl, w_old));
    rb[so + 34u] = 0.5lf * (dot(dp, v_cm) + dot(dl, omega));
    rb_set_vec(so + 3u, v_cm);
    rb_set_vec(so + 15u, ang_mom);
    rb_set_vec(so + 18u, omega);
    // next_placement: R^(n+1) = cay(omega dt) R^n, x_cm^(n+1) = x_cm + v_cm dt
    rb_set_vec(so + 21u, x_cm + v_cm * dt);
    rb_set_mat(so + 24u, mul3(hughes_winget(omega * (0.5lf * dt)), rot));
}

// ---------------------------------------------------------------- positions, end of a step

// x^(n+1) = x^n + dt v^(n+1/2) of node n into the other half of xs (halves).
fn move_node(n: u32, v: vec3<f64>, dt: f64) {
    let o = x_now + 3u * n;
    let p = x_next + 3u * n;
    xs[p] = xs[o] + v[0] * dt;
    xs[p + 1u] = xs[o + 1u] + v[1] * dt;
    xs[p + 2u] = xs[o + 2u] + v[2] * dt;
}

// x^(n+1) of every node from the state a restart file holds (x^n and v^(n+1/2) of a step that
// had begun): the nodes pass of that step wrote it on the device it ran on.
@compute @workgroup_size(64)
fn positions(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
             @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let n = 64u * (wid.y * nw.x + wid.x) + lid.x;
    if (f64(n) >= cf[SLOTS] || halted() || cf[PENDING] == 0.0lf) {
        return;
    }
    move_node(n, ld(1u, n), cf[DT]);
}

// The control block as the one-group passes (commit, control, finish) read it: loaded once
// by the group's threads together, so that the serial end of each pass (one thread) works
// on workgroup memory and not through a chain of round trips to device memory; each value
// it sets is written to both (put_cf).
var<workgroup> wcf: array<f64, 64>;
fn stage_cf(l: u32, threads: u32) {
    for (var k = l; k < 64u; k = k + threads) {
        wcf[k] = cf[k];
    }
    workgroupBarrier();
}
fn put_cf(k: u32, v: f64) {
    wcf[k] = v;
    cf[k] = v;
}

// The end of a step (solver.rs update_positions): t^(n+1) = t^n + dt, the step counted, the
// rigid bodies' placements committed, and the body loads' accelerations at the new time. The
// finish pass does it at the end of every step that does not halt; a step that halts (for
// output, a restart file, the end, an error) leaves it to the next batch's commit pass, so
// that the host reads the state at t^n.
fn advance() {
    put_cf(T, wcf[T] + wcf[DT]);
    put_cf(DT_PREV, wcf[DT]);
    put_cf(STEP, wcf[STEP] + 1.0lf);
    for (var b = 0u; b < prm.n_rigid; b = b + 1u) {
        let so = RB_STATE * b;
        for (var i = 0u; i < 12u; i = i + 1u) {
            rb[so + 36u + i] = rb[so + select(6u + i - 3u, i, i < 3u)];
        }
        for (var i = 0u; i < 3u; i = i + 1u) {
            rb[so + i] = rb[so + 21u + i];
        }
        for (var i = 0u; i < 9u; i = i + 1u) {
            rb[so + 6u + i] = rb[so + 24u + i];
        }
    }
    body_loads_now();
}

// The body loads' accelerations at t and at t - dt_prev.
fn body_loads_now() {
    let g = body_acceleration(wcf[T]);
    let gp = body_acceleration(wcf[T] - wcf[DT_PREV]);
    for (var i = 0u; i < 3u; i = i + 1u) {
        put_cf(G_NOW + i, g[i]);
        put_cf(G_PREV + i, gp[i]);
    }
}

// First in each batch of steps: the end of the step that halted, if one did (COMMIT_DUE), and
// the body loads at the start of a run.
@compute @workgroup_size(1)
fn commit() {
    halves();
    stage_cf(0u, 1u);
    if (halted()) {
        return;
    }
    if (wcf[COMMIT_DUE] != 0.0lf) {
        put_cf(COMMIT_DUE, 0.0lf);
        advance();
    } else {
        body_loads_now();
    }
}

// ---------------------------------------------------------------- control: the time step

var<workgroup> c_dt: array<f64, 256>;
var<workgroup> c_id: array<u32, 256>;
var<workgroup> c_ei: array<f64, 256>;
var<workgroup> c_eh: array<f64, 256>;
var<workgroup> c_ee: array<f64, 256>;
var<workgroup> c_en: array<f64, 256>;
var<workgroup> c_w: array<f64, 256>;
var<workgroup> c_om: array<f64, 256>;

// An element group's partials: its smallest time step and the element giving it, its
// internal, hourglass and eroded energy increments and its number of eroded elements. Stored
// by value, partial k of group g at k groups_e + g (and the node groups' likewise, at
// k groups_n + g), so that the one-group reductions' threads read neighbouring words.
struct EPart {
    dt: f64,
    id: u32,
    ei: f64,
    eh: f64,
    ee: f64,
    en: f64,
}
fn epart_at(g: u32) -> EPart {
    let gs = prm.groups_e;
    return EPart(epart[g], u32(epart[gs + g]), epart[2u * gs + g], epart[3u * gs + g], epart[4u * gs + g], epart[5u * gs + g]);
}
// r then p: the smaller step (the lower element on a tie), the sums in that order.
fn epart_add(r: EPart, p: EPart) -> EPart {
    var o = EPart(r.dt, r.id, r.ei + p.ei, r.eh + p.eh, r.ee + p.ee, r.en + p.en);
    if (p.dt < r.dt || (p.dt == r.dt && p.id < r.id)) {
        o.dt = p.dt;
        o.id = p.id;
    }
    return o;
}

fn fail(kind: u32) {
    atomicStore(&cu[ERROR], kind);
    atomicStore(&cu[HALT], 3u);
    cf[HALTED] = 1.0lf;
}

@compute @workgroup_size(256)
fn control(@builtin(local_invocation_id) lid: vec3<u32>) {
    halves();
    stage_cf(lid.x, 256u);
    let run = !halted();
    let l = lid.x;
    // thread l takes the element groups' partials l, l + 256, ... in that order, read four
    // groups ahead so that their loads overlap
    var r = EPart(BIG, 0xffffffffu, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
    if (run) {
        var g = l;
        while (g + 768u < prm.groups_e) {
            let p0 = epart_at(g);
            let p1 = epart_at(g + 256u);
            let p2 = epart_at(g + 512u);
            let p3 = epart_at(g + 768u);
            r = epart_add(epart_add(epart_add(epart_add(r, p0), p1), p2), p3);
            g = g + 1024u;
        }
        while (g < prm.groups_e) {
            r = epart_add(r, epart_at(g));
            g = g + 256u;
        }
    }
    // the softening faces: the work they absorbed, and the largest omega^2 = 2 K / m of the
    // slots their springs join (interfaces.rs cohesive_time_step)
    var wk = 0.0lf;
    var om = 0.0lf;
    if (run && prm.c_inc > 0u) {
        let nf = atomicLoad(&cu[N_COH]);
        for (var f = l; f < nf; f = f + 256u) {
            wk = wk + ifs[prm.c_coh + CO_STRIDE * f + 57u];
        }
        let ns = atomicLoad(&cu[N_CSLOT]);
        for (var i = l; i < ns; i = i + 256u) {
            let sl = ifu[prm.c_ptr + prm.c_slots + i];
            let kk = coh_stiffness(sl);
            let m = mass[sl];
            if (kk > 0.0lf && m > 0.0lf) {
                om = max(om, 2.0lf * kk / m);
            }
        }
    }
    c_w[l] = wk;
    c_om[l] = om;
    c_dt[l] = r.dt;
    c_id[l] = r.id;
    c_ei[l] = r.ei;
    c_eh[l] = r.eh;
    c_ee[l] = r.ee;
    c_en[l] = r.en;
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
            c_ee[l] = c_ee[l] + c_ee[o];
            c_en[l] = c_en[l] + c_en[o];
            c_w[l] = c_w[l] + c_w[o];
            c_om[l] = max(c_om[l], c_om[o]);
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
    put_cf(E_INT, wcf[E_INT] + c_ei[0]);
    put_cf(E_HG, wcf[E_HG] + c_eh[0]);
    put_cf(E_ERODED, wcf[E_ERODED] + c_ee[0]);
    put_cf(N_ERODED, wcf[N_ERODED] + c_en[0]);
    let dt_crit = c_dt[0];
    put_cf(DT_CRIT, dt_crit);
    let step0 = wcf[STEP] == 0.0lf;
    var d = wcf[TSSFAC] * dt_crit;
    // the contact springs' step (a constant: the CPU's, of the initial surfaces)
    if (cf[DT_CONTACT] < dt_crit) {
        d = wcf[TSSFAC] * cf[DT_CONTACT];
    }
    // the cohesive springs' own step (it holds its budget: not scaled by TSSFAC)
    if (c_om[0] > 0.0lf) {
        d = min(d, sqrt(2.0lf / c_om[0]));
    }
    put_cf(E_FRAC, wcf[E_FRAC] + c_w[0]);
    // no element limits the step (the CPU's infinite dt_crit): BIG is the reduction's start
    let none = dt_crit >= BIG || !finite(dt_crit);
    if (none && !step0 && wcf[N_ERODED] > 0.0lf) {
        // every deformable element has eroded: go on with the last step
        d = min(d, wcf[DT_PREV]);
    }
    if (wcf[DT_INIT] > 0.0lf && (step0 || none)) {
        d = min(d, wcf[DT_INIT]);
    }
    atomicStore(&cu[DT_ELEM], c_id[0]);
    put_cf(DT, d);
    if (step0) {
        put_cf(DT_FLOOR, wcf[DT_MIN] * d);
    } else if (d < wcf[DT_FLOOR]) {
        fail(2u);
        return;
    }
    if (!finite(d) || d <= 0.0lf) {
        fail(3u);
        return;
    }
    if (prm.dt_max_off != 0xffffffffu) {
        // LCTM, after the floor (curve.rs Curve::step_cap): its value, but for past its last
        // abscissa or where it is 0
        let o = prm.dt_max_off;
        let cap = curve_eval(o, wcf[T]);
        if (wcf[T] <= par[o + u32(par[o])] && cap != 0.0lf) {
            d = min(d, cap);
        }
    }
    let remaining = wcf[END_TIME] - wcf[T];
    if (remaining <= 1e-9lf * min(d, wcf[END_TIME])) {
        atomicStore(&cu[FINISHED], 1u);
    } else if (d > remaining) {
        d = remaining;
    }
    put_cf(DT, d);
    let dp = wcf[DT_PREV];
    put_cf(DT_MID, 0.5lf * (dp + d));
    var w = 0.0lf;
    if (step0) {
        w = 0.5lf;
    } else if (dp + d > 0.0lf) {
        w = dp / (dp + d);
    }
    put_cf(W_HALF, w);
}

// ---------------------------------------------------------------- interfaces: separation

// Element separation (cleave-core separation/interfaces.rs check_failure, criteria/): every
// intact interface checked on the stresses at t^n. The GPU's nodes are the coincident sets'
// slots (layout.rs Slots); the host keeps the sets and splits them. Per interface, in `ifu`
// (IF_STRIDE values): its two elements, its group, 1 while intact, and the slots of its 8
// nodes (side a's 4, then side b's, a triangle's fourth the third); in `ifs`: its strength,
// then (from n_if) each group's MODEL and BETA, then (from if_index) the failure indices of
// the interfaces that reached 1 in this step, in the order of `ifl`: the number of those, then
// their numbers (so the host reads the head of both, not an index per interface).
const IF_STRIDE: u32 = 12u;

// The interfaces pass: an interface whose failure index reached 1 is listed (the order of
// the list does not matter: the host sorts it); the halt comes in the next pass, so that every
// interface of this step is checked whichever thread finds one first.
@compute @workgroup_size(64)
fn interfaces(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
              @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let i = 64u * (wid.y * nw.x + wid.x) + lid.x;
    // (an inverted element has no stress to check: the control pass stops the run)
    if (i >= prm.n_if || halted() || atomicLoad(&cu[INVERTED]) != 0xffffffffu) {
        return;
    }
    let o = IF_STRIDE * i;
    if (ifu[o + 3u] == 0u) {
        return;
    }
    let ea = ifu[o];
    let eb = ifu[o + 1u];
    let g = ifu[o + 2u];
    let model = ifs[prm.n_if + 2u * g];
    let beta = ifs[prm.n_if + 2u * g + 1u];
    let strength = ifs[i];
    var sa: S6;
    var sb: S6;
    for (var k = 0u; k < 6u; k = k + 1u) {
        sa[k] = sig[ek(ea, k)];
        sb[k] = sig[ek(eb, k)];
    }
    // the cheap bound first (criteria/mod.rs: MODEL 1 tension_bound, the others
    // traction_bound times max(1, 1 / BETA); the slack of interfaces.rs check_failure)
    var bound = 0.5lf * (tension_row_bound(sa) + tension_row_bound(sb));
    if (model > 1.5lf) {
        bound = max(1.0lf, 1.0lf / beta) * 0.5lf * (row_bound(sa) + row_bound(sb));
    }
    if (bound < strength * (1.0lf - 1e-9lf)) {
        return;
    }
    let n = interface_normal(o);
    // the traction of the mean stress, its normal part and the magnitude of its shear part
    var m: S6;
    for (var k = 0u; k < 6u; k = k + 1u) {
        m[k] = 0.5lf * (sa[k] + sb[k]);
    }
    let t = vec3<f64>(m[0] * n[0] + m[3] * n[1] + m[5] * n[2],
                      m[3] * n[0] + m[1] * n[1] + m[4] * n[2],
                      m[5] * n[0] + m[4] * n[1] + m[2] * n[2]);
    let sn = dot(t, n);
    let ts = t - n * sn;
    let tau = sqrt(dot(ts, ts));
    // MODEL 1: n.s.n; MODELs 2-4: sqrt(<sn>^2 + (tau / BETA)^2) (Camacho and Ortiz)
    var measure = sn;
    if (model > 1.5lf) {
        let pos = max(sn, 0.0lf);
        let sh = tau / beta;
        measure = sqrt(pos * pos + sh * sh);
    }
    let index = measure / strength;
    if (index >= 1.0lf) {
        let k = atomicAdd(&ifl[0], 1u);
        atomicStore(&ifl[1u + k], i);
        ifs[prm.if_index + k] = index;
    }
}

// The current unit normal of the interface at `o` in `ifu`: the diagonal cross product of the
// mid-points of its 4 node pairs (interfaces.rs face_normal; zero for a degenerate face).
fn interface_normal(o: u32) -> vec3<f64> {
    var p: array<vec3<f64>, 4>;
    for (var k = 0u; k < 4u; k = k + 1u) {
        p[k] = (ld(0u, ifu[o + 4u + k]) + ld(0u, ifu[o + 8u + k])) * 0.5lf;
    }
    let c = cross(p[2] - p[0], p[3] - p[1]);
    let n2 = sqrt(dot(c, c));
    if (n2 == 0.0lf) {
        return vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    }
    return vec3<f64>(c[0] / n2, c[1] / n2, c[2] / n2);
}

// The largest signed row bound s_ii + sum_(j != i) |s_ij| of a symmetric stress (Gershgorin:
// at least n.s.n for any unit n; criteria/mod.rs tension_bound).
fn tension_row_bound(s: S6) -> f64 {
    let xy = abs(s[3]);
    let yz = abs(s[4]);
    let zx = abs(s[5]);
    return max(max(s[0] + xy + zx, s[1] + xy + yz), s[2] + yz + zx);
}

// The largest absolute row sum of a symmetric stress (Gershgorin: at least |s n| for any unit n).
fn row_bound(s: S6) -> f64 {
    let xy = abs(s[3]);
    let yz = abs(s[4]);
    let zx = abs(s[5]);
    return max(max(abs(s[0]) + xy + zx, abs(s[1]) + xy + yz), abs(s[2]) + yz + zx);
}

// After the interfaces: a step in which some failed halts here (HALT 4), before the nodes; the
// host releases them, splits the sets and runs the rest of the step.
@compute @workgroup_size(1)
fn interfaces_done() {
    halves();
    if (halted() || atomicLoad(&ifl[0]) == 0u) {
        return;
    }
    atomicStore(&cu[HALT], 4u);
    cf[HALTED] = 1.0lf;
}

// With contact, after the elements: a step in which elements eroded halts here (HALT 5),
// before the contact; the host drops their faces from the surfaces and adds the faces they
// covered (contact.rs), then runs the rest of the step, as the CPU erodes them before its
// contact (solver/erosion.rs erode_elements).
@compute @workgroup_size(1)
fn erosion_done() {
    if (halted() || atomicLoad(&cu[ERODED_NOW]) == 0u) {
        return;
    }
    atomicStore(&cu[ERODED_NOW], 0u);
    atomicStore(&cu[HALT], 5u);
    cf[HALTED] = 1.0lf;
}

// ---------------------------------------------------------------- cohesive laws: MODELs 3, 4

// The softening faces (separation/interfaces.rs add_cohesive_forces, cohesive.rs), in the
// order they were released, CO_STRIDE values each in `coh`: 0 the interface, 1 SIGMAX, 2 BETA,
// 3 delta_c, 4 the envelope (0 linear, 1 exponential), 5 the opening past the peak at which it
// is fully open, 6-9 each point's largest opening past the peak, 10-12 the onset traction t0,
// 13 k_max, 14 the reference area, 15 the points (4, a triangle 3), 16-27 the openings and
// 28-39 the forces at the last evaluation, 40 1 once every point is open (the face is free);
// and what a step leaves for the nodes and the time step: 41-52 each point's force on side
// a, 53-56 each point's spring stiffness between two sets, 57 the work absorbed. `cix`: per
// slot the start of its entries (one per slot and one more), the entries (face 8 k + point 2 p
// + side: 0 takes the force, 1 its opposite), then the slots that have entries. (`coh` is kept
// in `ifs` from c_coh, `cix` in `ifu` from c_ptr: a device binds at most 32 storage arrays to
// a pass on lavapipe, 31 on Apple's.)
const CO_STRIDE: u32 = 58u;

fn coh_envelope(o: u32, delta: f64) -> f64 {
    let x = delta / ifs[prm.c_coh + o + 3u];
    if (ifs[prm.c_coh + o + 4u] < 0.5lf) {
        return ifs[prm.c_coh + o + 1u] * max(1.0lf - x, 0.0lf);
    }
    return ifs[prm.c_coh + o + 1u] * (1.0lf + x) * exp64(-x);
}

fn coh_open(o: u32, soft: f64) -> bool {
    return soft >= ifs[prm.c_coh + o + 5u];
}

// The elastic stretch SIGMAX / k_max before the peak (0 for a rigid law).
fn coh_delta_e(o: u32, k_max: f64) -> f64 {
    if (finite(k_max)) {
        return ifs[prm.c_coh + o + 1u] / k_max;
    }
    return 0.0lf;
}

struct Traction {
    t: vec3<f64>,
    soft: f64,
}

// cohesive.rs CohesiveLaw::traction: the traction on side a for the opening d, with the
// point's largest opening past the peak updated.
fn coh_traction(o: u32, d_in: vec3<f64>, n: vec3<f64>, t0: vec3<f64>, k_max: f64, soft_in: f64) -> Traction {
    let beta = ifs[prm.c_coh + o + 2u];
    let b2 = beta * beta;
    let delta_e = coh_delta_e(o, k_max);
    var d = d_in;
    if (delta_e > 0.0lf) {
        let t0n = dot(t0, n);
        let t0s = t0 - n * t0n;
        d = d + (n * t0n + t0s * (1.0lf / b2)) * (1.0lf / k_max);
    }
    let dn = dot(d, n);
    let ds = d - n * dn;
    let dn_plus = max(dn, 0.0lf);
    let delta = sqrt(dn_plus * dn_plus + b2 * dot(ds, ds));
    var soft = soft_in;
    if (delta - delta_e > soft) {
        soft = delta - delta_e;
    }
    let delta_max = delta_e + soft;
    if (delta <= 0.0lf || delta_max <= 0.0lf || coh_open(o, soft)) {
        return Traction(vec3<f64>(0.0lf, 0.0lf, 0.0lf), soft);
    }
    let c = coh_envelope(o, soft) / delta_max;
    return Traction(ds * (b2 * c) + n * (dn_plus * c), soft);
}

// cohesive.rs CohesiveLaw::stiffest_slope.
fn coh_slope(o: u32, soft: f64, k_max: f64) -> f64 {
    if (coh_open(o, soft)) {
        return 0.0lf;
    }
    let delta_max = coh_delta_e(o, k_max) + soft;
    if (delta_max <= 0.0lf) {
        return BIG;
    }
    let beta = ifs[prm.c_coh + o + 2u];
    return max(beta * beta, 1.0lf) * coh_envelope(o, soft) / delta_max;
}

fn coh_vec(o: u32) -> vec3<f64> {
    return vec3<f64>(ifs[prm.c_coh + o], ifs[prm.c_coh + o + 1u], ifs[prm.c_coh + o + 2u]);
}

fn coh_store(o: u32, v: vec3<f64>) {
    ifs[prm.c_coh + o] = v[0];
    ifs[prm.c_coh + o + 1u] = v[1];
    ifs[prm.c_coh + o + 2u] = v[2];
}

// The cohesive pass: each softening face's tractions at its points (interfaces.rs
// face_tractions: each point opens normally by its own opening, all slide by the face's mean),
// the forces, the work since the last evaluation and the springs' stiffness.
@compute @workgroup_size(64)
fn cohesive(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
            @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let f = 64u * (wid.y * nw.x + wid.x) + lid.x;
    if (f >= atomicLoad(&cu[N_COH]) || halted()) {
        return;
    }
    let o = CO_STRIDE * f;
    // what the step leaves starts at zero, and stays so once the face is free
    for (var k = 41u; k < CO_STRIDE; k = k + 1u) {
        ifs[prm.c_coh + o + k] = 0.0lf;
    }
    if (ifs[prm.c_coh + o + 40u] != 0.0lf) {
        return;
    }
    let io = IF_STRIDE * u32(ifs[prm.c_coh + o]);
    let n = interface_normal(io);
    let pts = u32(ifs[prm.c_coh + o + 15u]);
    let w = ifs[prm.c_coh + o + 14u] / f64(pts);
    let t0 = coh_vec(o + 10u);
    let k_max = ifs[prm.c_coh + o + 13u];
    let inv = 1.0lf / f64(pts);
    var d: array<vec3<f64>, 4>;
    var dsum = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    for (var k = 0u; k < pts; k = k + 1u) {
        d[k] = ld(0u, ifu[io + 8u + k]) - ld(0u, ifu[io + 4u + k]);
        dsum = dsum + d[k];
    }
    let d_mean = dsum * inv;
    let ds = d_mean - n * dot(d_mean, n);
    var t: array<vec3<f64>, 4>;
    var ts_mean = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    var soft: array<f64, 4>;
    for (var k = 0u; k < pts; k = k + 1u) {
        let r = coh_traction(o, n * dot(d[k], n) + ds, n, t0, k_max, ifs[prm.c_coh + o + 6u + k]);
        soft[k] = r.soft;
        ifs[prm.c_coh + o + 6u + k] = r.soft;
        let tn = n * dot(r.t, n);
        ts_mean = ts_mean + (r.t - tn) * inv;
        t[k] = tn;
    }
    var slope = 0.0lf;
    for (var k = 0u; k < pts; k = k + 1u) {
        slope = max(slope, coh_slope(o, soft[k], k_max));
    }
    var work = 0.0lf;
    var open = true;
    for (var k = 0u; k < pts; k = k + 1u) {
        let fa = (t[k] + ts_mean) * w;
        let dp = coh_vec(o + 16u + 3u * k);
        let fp = coh_vec(o + 28u + 3u * k);
        work = work + 0.5lf * dot(fp + fa, d[k] - dp);
        coh_store(o + 16u + 3u * k, d[k]);
        coh_store(o + 28u + 3u * k, fa);
        coh_store(o + 41u + 3u * k, fa);
        open = open && coh_open(o, soft[k]);
        // the point's spring between two sets (none within one)
        if (ifu[io + 4u + k] != ifu[io + 8u + k]) {
            ifs[prm.c_coh + o + 53u + k] = slope * w;
        }
    }
    ifs[prm.c_coh + o + 57u] = work;
    if (open) {
        ifs[prm.c_coh + o + 40u] = 1.0lf;
    }
}

// The cohesive forces on slot n: its points' entries, in the faces' order.
fn coh_force(n: u32) -> vec3<f64> {
    var f = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    if (prm.c_inc == 0u) {
        return f;
    }
    for (var k = ifu[prm.c_ptr + n]; k < ifu[prm.c_ptr + n + 1u]; k = k + 1u) {
        let e = ifu[prm.c_ptr + prm.c_inc + k];
        let fa = coh_vec(CO_STRIDE * (e >> 3u) + 41u + 3u * ((e >> 1u) & 3u));
        if ((e & 1u) == 0u) {
            f = f + fa;
        } else {
            f = f - fa;
        }
    }
    return f;
}

// The stiffness of the springs on slot s (the sum over its entries).
fn coh_stiffness(s: u32) -> f64 {
    var kk = 0.0lf;
    for (var k = ifu[prm.c_ptr + s]; k < ifu[prm.c_ptr + s + 1u]; k = k + 1u) {
        let e = ifu[prm.c_ptr + prm.c_inc + k];
        kk = kk + ifs[prm.c_coh + CO_STRIDE * (e >> 3u) + 53u + ((e >> 1u) & 3u)];
    }
    return kk;
}

// ---------------------------------------------------------------- the nodes

const MAX_PART: u32 = 38u; // 6 + 4 x 8 rigid walls
var<workgroup> n_s: array<f64, 64>;
var<workgroup> n_s6: array<array<f64, 6>, 64>;

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


// The force on node n at t^n without its loads: its weight under the body loads and its
// elements' corner forces, gathered in element order.
fn node_force(n: u32) -> vec3<f64> {
    let g = vec3<f64>(cf[G_NOW], cf[G_NOW + 1u], cf[G_NOW + 2u]);
    var f = g * mass[n];
    for (var k = nptr[2u * n]; k < nptr[2u * n + 1u]; k = k + 1u) {
        let c = ninc[k];
        let e = c >> 3u;
        let a = c & 7u;
        let j = 3u * (a & 3u);
        if (a < 4u) {
            f = f + vec3<f64>(fe_lo[ek(e, j)], fe_lo[ek(e, j + 1u)], fe_lo[ek(e, j + 2u)]);
        } else {
            f = f + vec3<f64>(fe_hi[ek(e, j)], fe_hi[ek(e, j + 1u)], fe_hi[ek(e, j + 2u)]);
        }
    }
    return f;
}

// The node's concentrated loads and pressure segments at t (loads.rs), kept apart from its
// other forces for their work.
fn node_loads(n: u32, t: f64) -> vec3<f64> {
    var fl = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    for (var k = mptr[n]; k < mptr[n + 1u]; k = k + 1u) {
        let o = prm.mot_off + NODE_STRIDE * k;
        let kind = par[o];
        if (kind < 0.5lf || kind > 2.5lf) {
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
    return fl;
}

// The forces of the tied slave nodes whose faces node n carries: each slave's whole force (its
// elements' and loads') times the node's weight on the slave's face, in the ties' order
// (solver/tied.rs transfer_tied_forces).
fn tie_forces(n: u32, t: f64) -> vec3<f64> {
    var f = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    for (var k = mptr[n]; k < mptr[n + 1u]; k = k + 1u) {
        let o = prm.mot_off + NODE_STRIDE * k;
        if (par[o] < 2.5lf || par[o] > 3.5lf) {
            continue;
        }
        let sl = u32(par[o + 1u]);
        f = f + (node_force(sl) + node_loads(sl, t) + contact_force(sl)) * par[o + 2u];
    }
    return f;
}

// After the nodes: each tied slave node moves with its face, v_s = sum_a N_a v_a
// (solver/tied.rs move_tied_nodes).
@compute @workgroup_size(64)
fn tied(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
        @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let k = 64u * (wid.y * nw.x + wid.x) + lid.x;
    if (k >= prm.n_ties || halted()) {
        return;
    }
    let o = prm.tie_off + 9u * k;
    let sl = u32(par[o]);
    var v = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    var vn = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    for (var a = 0u; a < 4u; a = a + 1u) {
        let m = u32(par[o + 1u + a]);
        let w = par[o + 5u + a];
        v = v + ld(1u, m) * w;
        vn = vn + vec3<f64>(vns[3u * m], vns[3u * m + 1u], vns[3u * m + 2u]) * w;
    }
    for (var i = 0u; i < 3u; i = i + 1u) {
        vs[3u * sl + i] = v[i];
        vns[3u * sl + i] = vn[i];
    }
    move_node(sl, v, cf[DT]);
}

@compute @workgroup_size(64)
fn nodes(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
         @builtin(num_workgroups) nw: vec3<u32>) {
    halves();
    let n = 64u * (wid.y * nw.x + wid.x) + lid.x;
    let run = !halted();
    // the ledger's six values (kept apart from the walls', which only a deck with walls
    // indexes at run time)
    var acc = array<f64, 6>(0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
    var wacc: array<f64, WALL_VALUES>;
    if (run && f64(n) < cf[SLOTS]) {
        let m = mass[n];
        let t = cf[T];
        let fl = node_loads(n, t);
        var f = node_force(n) + fl + coh_force(n) + contact_force(n);
        if (prm.n_ties > 0u) {
            f = f + tie_forces(n, t);
        }
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
        // a rigid body's node: placed with its body, x^(n+1) = x_cm^(n+1) + R^(n+1) arm, by the
        // velocity (x^(n+1) - x^n) / dt (solver.rs update_rigid_bodies)
        let k = rbi[n];
        if (k != NOT_RIGID) {
            let eo = prm.rb_off + RB_PAR * prm.n_rigid + 4u * k;
            let so = RB_STATE * u32(par[eo]);
            let arm = vec3<f64>(par[eo + 1u], par[eo + 2u], par[eo + 3u]);
            let placed = rb_vec(so + 21u) + mat_vec3(rb_mat(so + 24u), arm);
            let v_new = (placed - ld(0u, n)) * (1.0lf / dt);
            vn = vn + (v_new - v) * w;
            v = v_new;
        }
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
            let kind = par[o];
            // not a motion, or not acting in this step (model.rs Window::holds)
            let tm = t + 0.5lf * dt;
            if ((kind > 0.5lf && kind < 3.5lf) || tm < par[o + 8u] || tm >= par[o + 9u]) {
                continue;
            }
            let c = u32(par[o + 4u]);
            // kind 0: along a global axis; 4 and 5: along the unit vector d (model.rs
            // MotionDof::apply)
            let along = kind > 3.5lf;
            let d = vec3<f64>(par[o + 1u], par[o + 6u], par[o + 7u]);
            let axis = select(u32(par[o + 1u]), 0u, along);
            var s = 0.0lf;
            if (par[o + 2u] < 0.5lf) {
                s = par[o + 3u] * curve_eval(c, t + 0.5lf * dt);
            } else {
                let goal = par[o + 5u] + par[o + 3u] * curve_eval(c, t + dt);
                let x = ld(0u, n);
                s = (goal - select(x[axis], dot(x, d), along)) / dt;
            }
            var vc = v;
            if (!along) {
                vc[axis] = s;
            } else if (kind > 4.5lf) {
                vc = d * s;
            } else {
                vc = v + d * (s - dot(v, d));
            }
            let r = constrain(m, w, v, vn, vc);
            v = r.v;
            vn = r.vn;
            acc[4] = acc[4] + r.now;
            acc[5] = acc[5] + r.later;
        }
        // rigid walls (solver.rs apply_rigid_walls): a node that would cross a wall's surface
        // in the next step lands on it; friction takes up to FRIC times the normal impulse
        for (var wl = 0u; wl < prm.n_walls; wl = wl + 1u) {
            if ((flags & (8u << wl)) == 0u) {
                continue;
            }
            let o = prm.wall_off + WALL_STRIDE * wl;
            var tail = vec3<f64>(par[o], par[o + 1u], par[o + 2u]);
            let ax = vec3<f64>(par[o + 3u], par[o + 4u], par[o + 5u]);
            let fric = par[o + 6u];
            // a moving wall (model.rs RigidWall::offset): where it is now, its velocity over
            // the step
            let moving = par[o + 15u] >= 0.0lf;
            var wv = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
            if (moving) {
                let c = u32(par[o + 15u]);
                let dir = vec3<f64>(par[o + 17u], par[o + 18u], par[o + 19u]);
                var d0 = 0.0lf;
                var d1 = 0.0lf;
                if (par[o + 16u] > 0.5lf) {
                    d0 = curve_eval(c, t);
                    d1 = curve_eval(c, t + dt);
                } else {
                    d0 = curve_integral(c, t);
                    d1 = curve_integral(c, t + dt);
                }
                tail = tail + dir * d0;
                wv = (dir * d1 - dir * d0) * (1.0lf / dt);
            }
            // the gap and outward normal (model.rs RigidWall::gap)
            let rel = ld(0u, n) - tail;
            var gap = 0.0lf;
            var nrm = ax;
            let shape = par[o + 12u];
            if (shape < 0.5lf) {
                gap = dot(rel, ax);
                // a finite plane: within LENL along l, LENM along n x l
                let len_l = par[o + 10u];
                if (len_l >= 0.0lf) {
                    let l = vec3<f64>(par[o + 7u], par[o + 8u], par[o + 9u]);
                    let a = dot(rel, l);
                    let b = dot(rel, cross(ax, l));
                    if (!(a >= 0.0lf && a <= len_l && b >= 0.0lf && b <= par[o + 11u])) {
                        continue;
                    }
                }
            } else {
                var q = rel;
                if (shape > 1.5lf) {
                    // a cylinder about the axis, over its length
                    let s = dot(rel, ax);
                    let len = par[o + 14u];
                    if (s < 0.0lf || (len >= 0.0lf && s > len)) {
                        continue;
                    }
                    q = rel - ax * s;
                }
                let d = sqrt(dot(q, q));
                if (!(d > 0.0lf)) {
                    continue;
                }
                gap = d - par[o + 13u];
                nrm = q * (1.0lf / d);
            }
            var vr = v;
            if (moving) {
                vr = v - wv;
            }
            let vnn = dot(vr, nrm);
            if (gap + dt * vnn >= 0.0lf) {
                continue;
            }
            var vn_new = 0.0lf;
            if (gap >= 0.0lf) {
                vn_new = -gap / dt;
            }
            let dvn = vn_new - vnn;
            let vt = vr - nrm * vnn;
            let vt_mag = sqrt(dot(vt, vt));
            var vt_new = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
            if (!(fric >= 1.0lf || vt_mag <= fric * dvn)) {
                vt_new = vt * (1.0lf - fric * dvn / vt_mag);
            }
            var v_new = nrm * vn_new + vt_new;
            if (moving) {
                v_new = wv + v_new;
            }
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
        move_node(n, v, dt);
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
    // the ledger's six values in one tree (the same shape for each as group_sum's)
    n_s6[l] = acc;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s = s >> 1u) {
        if (l < s) {
            let a = n_s6[l];
            let b = n_s6[l + s];
            n_s6[l] = array<f64, 6>(a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5]);
        }
        workgroupBarrier();
    }
    if (keep) {
        let t = n_s6[0];
        let gs = prm.groups_n;
        npart[g] = t[0];
        npart[gs + g] = t[1];
        npart[2u * gs + g] = t[2];
        npart[3u * gs + g] = t[3];
        npart[4u * gs + g] = t[4];
        npart[5u * gs + g] = t[5];
    }
    for (var k = 0u; k < 4u * prm.n_walls; k = k + 1u) {
        let s = group_sum(l, wacc[k]);
        if (keep) {
            npart[(6u + k) * prm.groups_n + g] = s;
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

// Thread l's sums of the six ledger values over the node groups' partials l, l + 256, ...,
// added in that order; the partials are read four groups ahead so that their loads overlap.
fn ledger_sums(l: u32) -> array<f64, 6> {
    var a = array<f64, 6>(0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
    var g = l;
    let groups = node_groups();
    while (g + 768u < groups) {
        let p0 = part6(g);
        let p1 = part6(g + 256u);
        let p2 = part6(g + 512u);
        let p3 = part6(g + 768u);
        a = add6(add6(add6(add6(a, p0), p1), p2), p3);
        g = g + 1024u;
    }
    while (g < groups) {
        a = add6(a, part6(g));
        g = g + 256u;
    }
    return a;
}
// The groups of the nodes pass that hold entries in use (the nodes pass is dispatched with
// those, stepper.rs Groups::Nodes).
fn node_groups() -> u32 {
    return (u32(cf[SLOTS]) + 63u) / 64u;
}
fn part6(g: u32) -> array<f64, 6> {
    let gs = prm.groups_n;
    return array<f64, 6>(npart[g], npart[gs + g], npart[2u * gs + g], npart[3u * gs + g], npart[4u * gs + g], npart[5u * gs + g]);
}
fn add6(a: array<f64, 6>, b: array<f64, 6>) -> array<f64, 6> {
    return array<f64, 6>(a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5]);
}

var<workgroup> f_s: array<f64, 256>;
var<workgroup> f_s6: array<array<f64, 6>, 256>;
var<workgroup> f_tot: array<f64, MAX_PART>;

@compute @workgroup_size(256)
fn finish(@builtin(local_invocation_id) lid: vec3<u32>) {
    halves();
    stage_cf(lid.x, 256u);
    let run = !halted();
    let l = lid.x;
    // each thread's sums over the partials g = l, l + 256, ... in that order, the six values of
    // the ledger together, then summed over the threads by one tree of fixed shape (the walls'
    // below, value by value, by trees of the same shape)
    var six = array<f64, 6>(0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
    if (run) {
        six = ledger_sums(l);
    }
    f_s6[l] = six;
    workgroupBarrier();
    for (var s = 128u; s > 0u; s = s >> 1u) {
        if (l < s) {
            f_s6[l] = add6(f_s6[l], f_s6[l + s]);
        }
        workgroupBarrier();
    }
    if (l < 6u) {
        f_tot[l] = f_s6[0][l];
    }
    for (var k = 6u; k < prm.n_part; k = k + 1u) {
        var acc = 0.0lf;
        if (run) {
            for (var g = l; g < node_groups(); g = g + 256u) {
                acc = acc + npart[k * prm.groups_n + g];
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
    workgroupBarrier();
    if (l != 0u || !run) {
        return;
    }
    var ke = f_tot[0];
    if (atomicLoad(&cu[NONFINITE]) != 0xffffffffu || !finite(ke)) {
        fail(4u);
        return;
    }
    // the mass of the bodies with a given inertia, which no node carries
    var p_old = vec3<f64>(f_tot[1], f_tot[2], f_tot[3]);
    for (var b = 0u; b < prm.n_rigid; b = b + 1u) {
        let u = rb_unlumped(b);
        ke = ke + u.ke;
        p_old = p_old + u.p;
    }
    put_cf(E_KIN, ke);
    var body = 0.0lf;
    let dp = wcf[DT_PREV];
    if (prm.n_body > 0u && dp != 0.0lf) {
        let g = vec3<f64>(wcf[G_PREV], wcf[G_PREV + 1u], wcf[G_PREV + 2u]) + vec3<f64>(wcf[G_NOW], wcf[G_NOW + 1u], wcf[G_NOW + 2u]);
        body = 0.5lf * dot(g, p_old) * dp;
    }
    // the work of the rigid bodies' constraints and prescribed motions, body after body
    var rb_now = 0.0lf;
    var rb_later = 0.0lf;
    for (var b = 0u; b < prm.n_rigid; b = b + 1u) {
        rb_now = rb_now + rb[RB_STATE * b + 33u];
        rb_later = rb_later + rb[RB_STATE * b + 34u];
    }
    put_cf(E_EXT, wcf[E_EXT] + wcf[PENDING_WORK] + f_tot[4] + rb_now + body);
    put_cf(PENDING_WORK, f_tot[5] + rb_later);
    var inv = 0.0lf;
    if (wcf[DT_MID] > 0.0lf) {
        inv = 1.0lf / wcf[DT_MID];
    }
    for (var wl = 0u; wl < prm.n_walls; wl = wl + 1u) {
        for (var k = 0u; k < 4u; k = k + 1u) {
            put_cf(WALL_FORCE + 4u * wl + k, f_tot[6u + 4u * wl + k] * inv);
        }
    }
    if (wcf[STEP] == 0.0lf) {
        put_cf(E_INIT, ke + wcf[E_INT] + wcf[E_HG] - wcf[E_EXT]);
    }
    // the positions are due at every step from here on (the next positions pass)
    put_cf(PENDING, 1.0lf);
    if (atomicLoad(&cu[FINISHED]) != 0u) {
        atomicStore(&cu[HALT], 2u);
        put_cf(HALTED, 1.0lf);
        put_cf(COMMIT_DUE, 1.0lf);
    } else if (wcf[T] >= wcf[T_STOP] * (1.0lf - 1e-12lf)) {
        atomicStore(&cu[HALT], 1u);
        put_cf(HALTED, 1.0lf);
        put_cf(COMMIT_DUE, 1.0lf);
    } else {
        advance();
    }
}
