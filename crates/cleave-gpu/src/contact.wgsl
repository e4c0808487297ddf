// Automatic contact on the GPU: cleave-core contact/ (mod.rs NodeCheck, penalty.rs,
// engagement.rs, friction.rs), operation for operation, with a broad phase of its own. The
// Rust doc comments there carry the formulas and their sources.
//
// Each pass of a definition checks its node side's nodes (the *pass-nodes*, numbered over all
// passes in the order the CPU scatters their forces) against the faces of its face side. Every
// step, with no schedule (a bound on the motion only says when the candidate lists are made
// again):
//   c_close (per closed crack)  the closed cracks' step (contact/closure.rs): their pairs'
//                            forces, or their release
//   c_close_done (1 thread)  halts the step when some were released (HALT 6: the host lets
//                            them go, and the device in place, then runs the rest)
//   c_count (per face)       each face's search sphere, centre c (the corners' mean) and
//                            radius E r + depth (grown by the lists' margin once they may be
//                            used), in the cells of a hashed grid its box overlaps (their
//                            count; the span kept for c_fill); a face whose box spans more
//                            than SPAN cells a side goes to a list every node reads (`big`);
//                            the bounds of its corners' displacements since the lists were made
//   c_sums, c_scan, c_offsets  the cells' offsets (an exclusive sum: each block's sum, the
//                            blocks' offsets by one group, the offsets in each block); c_scan
//                            also decides whether the lists are used, made again, or not yet
//                            (the tables are new): the mode of the step
//   c_fill (per face)        the faces into their cells (when a node reads them), and the
//                            corners where the lists are made
//   c_detect (C_LANES threads a pass-node)  the node against every face of its list (or of
//                            its cell, and then its list made): the nearest contact (least
//                            penetration, of equal ones the lowest face), its engagement,
//                            normal and friction force; counted per face
//   c_hsums, c_hscan, c_hoffsets  each face's offset in the list of the nodes that hit it
//   c_hfill (per pass-node)  that list
//   c_hsort (per face)       a short list in pass-node order, and the reactions on the face's
//                            corners added in that order; a long list to c_hlong
//   c_hlong (fixed groups)   the long lists the same way, a group of 64 threads a face
//   c_gather (per node of a surface)  the node's contact force: the closed cracks' pairs at
//                            it, its own hits in pass-node order, then the reactions on the
//                            faces it holds, face by face; the work of the last step's and
//                            this step's forces over the step (partials per group)
//   c_energy (1 group)       the contact energy, -1/2 dt sum (f^(n-1) + f^n).v^(n-1/2)
// A node in the face's sphere shares a cell with it (the face is in every cell its sphere's
// box touches), and is on the node's list while the list is in use (c_scan), so no contact
// the CPU's search finds is missed; the order faces come in does not change which one wins. The forces are written per entry (a model node, or with
// element separation a coincident set's slot: positions, velocities and forces are read and
// written there) to `fcon`, which the step (step.wgsl node_force's callers) adds to the other
// forces. With separation the pass-nodes are the sets' leads, a face holding a copy of the
// node's chain label is left out, and the closed cracks' pairs add their forces before the
// pass-nodes', as on the CPU.
//
// The sizes (C_NN nodes, C_NF faces, C_NP pass-nodes, C_NG surface nodes, C_M cells), the
// offsets of the tables in `ci` and `cfl` and of the grid's and hit lists' parts are the first
// values of `ci`, read into private variables by `params()` first thing in every entry point
// (the host declares them before this text, contact_tables.rs PARAMS): the tables are rebuilt when
// the surfaces or sets change (elements erode, interfaces fail, closed cracks are released)
// without compiling the shader again.
//
// One difference from the CPU: a lead all of whose faces lie on tight closed cracks is buried
// (not checked) from the step its cracks are tight, where the CPU buries it from its next
// search (mod.rs Side::buried, at the searches). Burial only skips nodes inside the material,
// each face held flush by its crack's pairs: a body could reach one only between the two faces
// of a crack, so the two give the same results (the tests compare them with cracks closing,
// opening and shutting again).

@group(0) @binding(0) var<storage, read_write> cf: array<f64>;
@group(0) @binding(1) var<storage, read> xs: array<f64>;
@group(0) @binding(2) var<storage, read> vs: array<f64>;
@group(0) @binding(3) var<storage, read> ci: array<u32>;
@group(0) @binding(4) var<storage, read> cfl: array<f64>;
@group(0) @binding(5) var<storage, read_write> hits: array<f64>;
@group(0) @binding(6) var<storage, read_write> fcon: array<f64>;
@group(0) @binding(7) var<storage, read_write> fprev: array<f64>;
@group(0) @binding(8) var<storage, read_write> grid: array<atomic<u32>>;
@group(0) @binding(9) var<storage, read_write> cpart: array<f64>;
// each face's values of this step, FS a face: its sphere (c_count: centre, r), then the
// reactions on its 4 corners of the nodes that push on it (c_hsort, c_hlong: 3 each), then its
// corners where the candidate lists were last made (c_fill: 3 each, at REF); after the faces,
// each c_count group's bounds of its corners' displacements since then (BOUNDS values each:
// the least, then the greatest, of each component)
@group(0) @binding(10) var<storage, read_write> fsph: array<f64>;
const FS: u32 = 28u;
const REF: u32 = 16u;
const BOUNDS: u32 = 6u;
// the closed cracks' states (CLO values each) and the step's control integers (c_close_done
// halts the step: HALT 6)
@group(0) @binding(11) var<storage, read_write> clo: array<f64>;
@group(0) @binding(12) var<storage, read_write> cu: array<atomic<u32>>;

const DT_PREV: u32 = 1u;
const STEP: u32 = 3u;
const HALTED: u32 = 22u;
const E_CONTACT: u32 = 64u;
const NONE: u32 = 0xffffffffu;

// contact/penalty.rs INSIDE_TOL, WEIGHT_SUM, MAX_ITER, NEWTON_TOL; mod.rs GAP_TOL, FACING
const INSIDE_TOL: f64 = 0.02lf;
const WEIGHT_SUM: f64 = 1.08lf;
const MAX_ITER: u32 = 12u;
const NEWTON_TOL: f64 = 1e-11lf;
const GAP_TOL: f64 = 1e-9lf;
const FACING: f64 = 0.2lf;
// a face whose sphere's box spans more than SPAN cells along an axis (hi - lo >= SPAN) goes
// to the `big` list: at most SPAN^3 = 27 cells a face in the grid (contact_tables.rs CELLS)
const SPAN: f64 = 3.0lf;

// A hit, HIT values per pass-node: the face (-1: none), the weights w_a of its corners at the
// contact point, the force on the node f, the engaged penetration and offset (engagement.rs),
// |f_n|, and the tangential force f_t (friction.rs; kept for the next step).
const HIT: u32 = 14u;

// A pass-node in `ci` (at CI_PN, PN values each): the entry of its node (its coincident set's
// slot, or the node), its pass, 1 when it is buried for good (every face of its set eroded),
// the label of its chain (mod.rs Chains: a face that holds a node of that label is not
// tested).
const PN: u32 = 4u;

// A closed crack (contact/closure.rs): in `ci` at CI_CLO, 9 values each (the entries of A's
// nodes a_k, of their partners b_k, its definition), its penalty at CF_CK in `cfl`, and its
// state in `clo`, CLO values each: the tangential force on each b_k (0-11), the mid-surface
// normal (12-14), each pair's normal force (15-18), 1 while tight (19), 1 in the step it is
// released (20).
const CLO: u32 = 21u;
// closure.rs SLIP, TIGHT, TURN
const SLIP: f64 = 0.2lf;
const TIGHT: f64 = 0.2lf;
const TURN: f64 = 0.866lf;
// cu: the halt code (step.wgsl HALT)
const CU_HALT: u32 = 0u;

fn halted() -> bool {
    return cf[HALTED] != 0.0lf;
}

fn finite3(v: vec3<f64>) -> bool {
    return finite(v.x) && finite(v.y) && finite(v.z);
}

var<private> x_now: u32;
fn halves() {
    x_now = u32(cf[STEP] % 2.0lf) * 3u * C_NN;
}

fn pos(n: u32) -> vec3<f64> {
    let o = x_now + 3u * n;
    return vec3<f64>(xs[o], xs[o + 1u], xs[o + 2u]);
}

fn vel(n: u32) -> vec3<f64> {
    return vec3<f64>(vs[3u * n], vs[3u * n + 1u], vs[3u * n + 2u]);
}

fn face_node(f: u32, a: u32) -> u32 {
    return ci[CI_FACE + 4u * f + a];
}

fn corners(f: u32) -> array<vec3<f64>, 4> {
    return array<vec3<f64>, 4>(pos(face_node(f, 0u)), pos(face_node(f, 1u)), pos(face_node(f, 2u)), pos(face_node(f, 3u)));
}

// x(xi, eta) = a0 + a1 xi + a2 eta + a3 xi eta (penalty.rs coefficients), component by
// component in the CPU's order.
fn coeff(p: array<vec3<f64>, 4>, s0: f64, s1: f64, s2: f64, s3: f64) -> vec3<f64> {
    return vec3<f64>(
        0.25lf * (s0 * p[0].x + s1 * p[1].x + s2 * p[2].x + s3 * p[3].x),
        0.25lf * (s0 * p[0].y + s1 * p[1].y + s2 * p[2].y + s3 * p[3].y),
        0.25lf * (s0 * p[0].z + s1 * p[1].z + s2 * p[2].z + s3 * p[3].z));
}

// ---------------------------------------------------------------- closed cracks

fn diagonal_cross(p: array<vec3<f64>, 4>) -> vec3<f64> {
    return cross(p[2] - p[0], p[3] - p[1]);
}

// One closed crack's step (closure.rs Closure::step): released when its faces no longer lie
// on each other (a pair slid by more than SLIP of A's shortest edge, or the faces turned apart
// past TURN), else each pair's penalty on its normal opening, with friction, and whether it is
// still tight. A release is counted (c_close_done halts the step for the host).
@compute @workgroup_size(64)
fn c_close(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
           @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    halves();
    let c = pass_index(wid, nw, lid.x);
    if (c >= C_NC || halted()) {
        return;
    }
    let t = CI_CLO + 9u * c;
    let o = CLO * c;
    // (one let go in an earlier step, its state zero: contact.rs release_in_place)
    if (clo[o + 20u] != 0.0lf) {
        return;
    }
    var pa: array<vec3<f64>, 4>;
    var pb: array<vec3<f64>, 4>;
    var m: array<vec3<f64>, 4>;
    for (var k = 0u; k < 4u; k = k + 1u) {
        pa[k] = pos(ci[t + k]);
        pb[k] = pos(ci[t + 4u + k]);
        m[k] = (pa[k] + pb[k]) * 0.5lf;
    }
    var edge2 = BIG;
    for (var k = 0u; k < 4u; k = k + 1u) {
        let e = pa[(k + 1u) % 4u] - pa[k];
        edge2 = min(edge2, dot(e, e));
    }
    // both normals in A's node order: flush faces give na . nb = |na| |nb|
    let na = diagonal_cross(pa);
    let nb = diagonal_cross(pb);
    let la = sqrt(dot(na, na));
    let lb = sqrt(dot(nb, nb));
    let cm = diagonal_cross(m);
    let lc = sqrt(dot(cm, cm));
    var released = !(la > 0.0lf && lb > 0.0lf && lc > 0.0lf) || dot(na, nb) < TURN * la * lb;
    var n = vec3<f64>(0.0lf);
    var d: array<vec3<f64>, 4>;
    if (!released) {
        // unit normal of the mid-surface, out of A
        n = cm * (1.0lf / lc);
        let lim = SLIP * SLIP * edge2;
        for (var k = 0u; k < 4u; k = k + 1u) {
            d[k] = pb[k] - pa[k];
            let tv = d[k] - n * dot(d[k], n);
            let t2 = dot(tv, tv);
            if (t2 > lim || !finite(t2)) {
                released = true;
            }
        }
    }
    if (released) {
        clo[o + 20u] = 1.0lf;
        atomicAdd(&grid[G_REL], 1u);
        return;
    }
    for (var i = 0u; i < 3u; i = i + 1u) {
        clo[o + 12u + i] = n[i];
    }
    let open = TIGHT * TIGHT * edge2;
    var tight = true;
    let def = ci[t + 8u];
    let kp = cfl[CF_CK + c];
    for (var k = 0u; k < 4u; k = k + 1u) {
        let g = dot(d[k], n);
        if (g >= 0.0lf || !finite(g)) {
            tight = tight && g * g <= open;
            for (var i = 0u; i < 3u; i = i + 1u) {
                clo[o + 3u * k + i] = 0.0lf;
            }
            clo[o + 15u + k] = 0.0lf;
            continue;
        }
        let fn_mag = -kp * g;
        if (!frictionless(def)) {
            let v_rel = vel(ci[t + 4u + k]) - vel(ci[t + k]);
            let v_t = v_rel - n * dot(v_rel, n);
            let mu = mu_of(def, sqrt(dot(v_t, v_t)));
            let ft_prev = vec3<f64>(clo[o + 3u * k], clo[o + 3u * k + 1u], clo[o + 3u * k + 2u]);
            let f_t = tangential(ft_prev, n, v_t * cf[DT_PREV], kp, mu * fn_mag);
            for (var i = 0u; i < 3u; i = i + 1u) {
                clo[o + 3u * k + i] = f_t[i];
            }
        }
        clo[o + 15u + k] = fn_mag;
    }
    clo[o + 19u] = select(0.0lf, 1.0lf, tight);
}

// A step in which closed cracks were released halts here (HALT 6): the host lets them go
// (their node pairs no longer chain their copies) and so does the device, their states zeroed
// and the chain labels written again (contact.rs release_in_place), then runs the rest of the
// step, as the CPU releases them before its node checks (mod.rs
// Contact::compute).
@compute @workgroup_size(1)
fn c_close_done() {
    params();
    if (halted() || atomicLoad(&grid[G_REL]) == 0u) {
        return;
    }
    atomicStore(&grid[G_REL], 0u);
    atomicStore(&cu[CU_HALT], 6u);
    cf[HALTED] = 1.0lf;
}

// ---------------------------------------------------------------- the broad phase

// The search sphere of a face at corners p: centre (the corners' mean, penalty.rs FaceBounds
// c), radius E r + depth (FaceBounds::may_touch), r the largest centre-corner distance (w: r).
fn sphere(p: array<vec3<f64>, 4>) -> vec4<f64> {
    let c = coeff(p, 1.0lf, 1.0lf, 1.0lf, 1.0lf);
    var r2 = 0.0lf;
    for (var a = 0u; a < 4u; a = a + 1u) {
        let d = p[a] - c;
        r2 = max(r2, dot(d, d));
    }
    return vec4<f64>(c, sqrt(r2));
}

// The cell of point q, each index clamped to +-1e9 (a node or face far away shares the edge
// cells with others: more tests, never fewer).
fn cell_of(q: vec3<f64>) -> vec3<f64> {
    let h = cfl[CF_H];
    return clamp(floor(q / h), vec3<f64>(-1e9lf), vec3<f64>(1e9lf));
}

fn hash(c: vec3<f64>) -> u32 {
    let u = bitcast<vec3<u32>>(vec3<i32>(c));
    return ((u.x * 73856093u) ^ (u.y * 19349663u) ^ (u.z * 83492791u)) & (C_M - 1u);
}

// The cells face f's sphere box spans: lo, hi (inclusive); lo.x > hi.x when the face has no
// finite position; hi - lo beyond SPAN: the face goes to the `big` list.
struct Span {
    lo: vec3<f64>,
    hi: vec3<f64>,
}

fn span_of(f: u32, s: vec4<f64>) -> Span {
    let c = s.xyz;
    // (1 + 1e-9) and 1e-300: the box holds every point the exact sphere holds
    let r = reach_of(f, s.w, lists_in_reach()) + 1e-300lf;
    if (!finite3(c) || !finite(r)) {
        return Span(vec3<f64>(1.0lf), vec3<f64>(0.0lf));
    }
    return Span(cell_of(c - vec3<f64>(r)), cell_of(c + vec3<f64>(r)));
}

// The radius of face f's search sphere, E r + depth, grown by (1 + E) mu for the candidate
// lists when `grown` (c_scan), with a relative 1e-9 so that the sphere holds every point the
// exact one holds.
fn reach_of(f: u32, r: f64, grown: bool) -> f64 {
    var reach = WEIGHT_SUM * r + cfl[CF_DEPTH + f];
    if (grown) {
        reach = reach + (1.0lf + WEIGHT_SUM) * cfl[CF_MU];
    }
    return reach * (1.0lf + 1e-9lf);
}

// The candidate lists are made, or may be in this step: the tables have lasted WAIT steps
// (c_scan), and lists are kept (C_K). Until then the grid holds the faces' spheres as they are.
fn lists_in_reach() -> bool {
    return C_K > 0u && atomicLoad(&grid[G_FLAGS]) >= WAIT;
}

fn is_big(s: Span) -> bool {
    let d = s.hi - s.lo;
    return d.x >= SPAN || d.y >= SPAN || d.z >= SPAN;
}

fn pass_index(w: vec3<u32>, nw: vec3<u32>, l: u32) -> u32 {
    return 64u * (w.y * nw.x + w.x) + l;
}

// Face f into the cells of span `s`: counted (`fill` false) or written into the cells'
// entries (true; a face over SPAN cells a side into the `big` list instead).
fn put_face(f: u32, s: Span, fill: bool) {
    if (s.lo.x > s.hi.x) {
        return;
    }
    if (is_big(s)) {
        if (fill) {
            let k = atomicAdd(&grid[G_BIGN], 1u);
            atomicStore(&grid[G_BIG + k], f);
        }
        return;
    }
    for (var i = s.lo.x; i <= s.hi.x; i = i + 1.0lf) {
        for (var j = s.lo.y; j <= s.hi.y; j = j + 1.0lf) {
            for (var k = s.lo.z; k <= s.hi.z; k = k + 1.0lf) {
                let b = hash(vec3<f64>(i, j, k));
                if (fill) {
                    let at = atomicLoad(&grid[G_OFF + b]) + atomicAdd(&grid[G_FILL + b], 1u);
                    atomicStore(&grid[G_ENT + at], f);
                } else {
                    atomicAdd(&grid[G_COUNT + b], 1u);
                }
            }
        }
    }
}

// Each face's span as the count found it, kept for the fill (6 values a face: the cells' lo
// and hi, as i32), so that the two passes put a face in the same cells whatever the compiler
// makes of the arithmetic in each.
fn keep_span(f: u32, s: Span) {
    let lo = bitcast<vec3<u32>>(vec3<i32>(s.lo));
    let hi = bitcast<vec3<u32>>(vec3<i32>(s.hi));
    let o = G_SPAN + 6u * f;
    atomicStore(&grid[o], lo.x);
    atomicStore(&grid[o + 1u], lo.y);
    atomicStore(&grid[o + 2u], lo.z);
    atomicStore(&grid[o + 3u], hi.x);
    atomicStore(&grid[o + 4u], hi.y);
    atomicStore(&grid[o + 5u], hi.z);
}

fn kept_span(f: u32) -> Span {
    let o = G_SPAN + 6u * f;
    let lo = vec3<u32>(atomicLoad(&grid[o]), atomicLoad(&grid[o + 1u]), atomicLoad(&grid[o + 2u]));
    let hi = vec3<u32>(atomicLoad(&grid[o + 3u]), atomicLoad(&grid[o + 4u]), atomicLoad(&grid[o + 5u]));
    return Span(vec3<f64>(bitcast<vec3<i32>>(lo)), vec3<f64>(bitcast<vec3<i32>>(hi)));
}

@compute @workgroup_size(64)
fn c_count(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
           @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    halves();
    let f = pass_index(wid, nw, lid.x);
    let run = !halted();
    var lo = vec3<f64>(BIG);
    var hi = vec3<f64>(-BIG);
    if (f < C_NF && run) {
        let p = corners(f);
        let sp = sphere(p);
        for (var k = 0u; k < 4u; k = k + 1u) {
            fsph[FS * f + k] = sp[k];
        }
        let s = span_of(f, sp);
        keep_span(f, s);
        put_face(f, s, false);
        for (var a = 0u; a < 4u; a = a + 1u) {
            let o = FS * f + REF + 3u * a;
            let d = p[a] - vec3<f64>(fsph[o], fsph[o + 1u], fsph[o + 2u]);
            if (finite3(d)) {
                lo = min(lo, d);
                hi = max(hi, d);
            }
        }
    }
    // the group's bounds of its corners' displacements (c_scan takes them all)
    bounds_in_group(lid.x, 64u, lo, hi);
    // (not the groups that only pad a dispatch of two dimensions: past the bounds' room)
    if (lid.x == 0u && run && group_index(wid, nw) < (C_NF + 63u) / 64u) {
        let o = FS * C_NF + BOUNDS * group_index(wid, nw);
        for (var k = 0u; k < 3u; k = k + 1u) {
            fsph[o + k] = b_lo[0][k];
            fsph[o + 3u + k] = b_hi[0][k];
        }
    }
}

@compute @workgroup_size(64)
fn c_fill(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
          @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    let f = pass_index(wid, nw, lid.x);
    let mode = atomicLoad(&grid[G_FLAGS + 1u]);
    let build = mode == BUILD;
    let cells = mode != LISTS || atomicLoad(&grid[G_FLAGS + 2u]) != 0u || C_VERIFY != 0u;
    if (f < C_NF && !halted() && cells) {
        put_face(f, kept_span(f), true);
    }
    if (f < C_NF && !halted() && build) {
        // the corners where the lists are made
        let p = corners(f);
        for (var a = 0u; a < 4u; a = a + 1u) {
            for (var k = 0u; k < 3u; k = k + 1u) {
                fsph[FS * f + REF + 3u * a + k] = p[a][k];
            }
        }
    }
}

// Exclusive sums of the `len` counts at `count` in `grid` into `off` (len + 1 values), the
// counts and the fill cursors at `fill` set back to zero for the next step, in three passes
// (a scan by one group over a million cells was 5-7% of the ball's step on an H100): the sum
// of each block of BLOCK counts (a group of 256 threads, 4 counts each; c_sums, c_hsums), the
// blocks' offsets (one group; c_scan, c_hscan), the offsets within each block (c_offsets,
// c_hoffsets). The blocks' sums and offsets are at G_PART, shared by the two scans.
const BLOCK: u32 = 1024u;
var<workgroup> s_sum: array<u32, 256>;

fn group_index(w: vec3<u32>, nw: vec3<u32>) -> u32 {
    return w.y * nw.x + w.x;
}

// inclusive sums of s_sum (Hillis-Steele)
fn sums_in_group(l: u32) {
    for (var d = 1u; d < 256u; d = d << 1u) {
        var add = 0u;
        if (l >= d) {
            add = s_sum[l - d];
        }
        workgroupBarrier();
        s_sum[l] = s_sum[l] + add;
        workgroupBarrier();
    }
}

// Thread l's counts of block g: [a, b).
fn block_run(g: u32, l: u32, len: u32) -> vec2<u32> {
    let a = min(g * BLOCK + 4u * l, len);
    return vec2<u32>(a, min(a + 4u, len));
}

// The sum of thread l's counts of block g (at `count`), put in s_sum and summed over the
// group (inclusive sums: the block's at 255).
fn group_sums(count: u32, len: u32, g: u32, l: u32) -> u32 {
    let r = block_run(g, l, len);
    var sum = 0u;
    for (var i = r.x; i < r.y; i = i + 1u) {
        sum = sum + atomicLoad(&grid[count + i]);
    }
    s_sum[l] = sum;
    workgroupBarrier();
    sums_in_group(l);
    return sum;
}

fn block_sums(count: u32, len: u32, g: u32, l: u32, run: bool) {
    group_sums(count, len, g, l);
    if (l == 0u && run && g * BLOCK < len) {
        atomicStore(&grid[G_PART + g], s_sum[255]);
    }
}

// The blocks' sums at G_PART into their offsets, in place.
fn block_offsets(len: u32, l: u32, run: bool) {
    let n = (len + BLOCK - 1u) / BLOCK;
    let per = (n + 255u) / 256u;
    let a = min(l * per, n);
    let b = min(a + per, n);
    var sum = 0u;
    for (var i = a; i < b; i = i + 1u) {
        sum = sum + atomicLoad(&grid[G_PART + i]);
    }
    s_sum[l] = sum;
    workgroupBarrier();
    sums_in_group(l);
    if (!run) {
        return;
    }
    var at = s_sum[l] - sum;
    for (var i = a; i < b; i = i + 1u) {
        let v = atomicLoad(&grid[G_PART + i]);
        atomicStore(&grid[G_PART + i], at);
        at = at + v;
    }
}

fn offsets(count: u32, off: u32, fill: u32, len: u32, g: u32, l: u32, run: bool) {
    let r = block_run(g, l, len);
    let sum = group_sums(count, len, g, l);
    if (!run || g * BLOCK >= max(len, 1u)) {
        return;
    }
    var at = 0u;
    if (len > 0u) {
        at = atomicLoad(&grid[G_PART + g]) + s_sum[l] - sum;
    }
    for (var i = r.x; i < r.y; i = i + 1u) {
        atomicStore(&grid[off + i], at);
        at = at + atomicLoad(&grid[count + i]);
        atomicStore(&grid[count + i], 0u);
        atomicStore(&grid[fill + i], 0u);
    }
    // the thread of the last count (of none: the first) ends the offsets
    if (r.y == len && (r.x < r.y || (len == 0u && l == 0u))) {
        atomicStore(&grid[off + len], at);
    }
}

@compute @workgroup_size(256)
fn c_sums(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
          @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    block_sums(G_COUNT, C_M, group_index(wid, nw), lid.x, !halted());
}

// The candidate lists (c_detect) hold, for each pass-node, the faces whose search sphere
// grown by (1 + E) mu held it where the lists were made (each face's corners then at REF, and
// the node a corner of a face of its side). Every position since lies in the box of the
// corners' displacements, of diagonal delta: the node moved by at most delta relative to a
// face's centre (a mean of its corners) and the face's radius grew by at most delta, so a
// face whose sphere holds the node now is on its list while delta <= mu. c_scan makes them
// again when the diagonal is past mu. Tables are made again at every split, and a fragmenting
// body splits in most steps for a while: the lists are first made once the tables have lasted
// WAIT steps (G_FLAGS: the steps so far, to WAIT), and until then each node is checked against
// its cell. G_FLAGS + 1: this step's mode (LISTS, BUILD, CELLS); + 2: some node had more
// candidates than its list holds (the grid is then filled every step for it); + 3: the lists
// made so far; + 4: the lists are made; for tests (C_VERIFY), + 5: the faces a list missed,
// + 6: the faces looked for (c_detect verify).
const WAIT: u32 = 8u;
const LISTS: u32 = 0u;
const BUILD: u32 = 1u;
const CELLS: u32 = 2u;
// (3 values each, not vec3: a vec3<f64> takes 32 bytes, and with s_sum c_scan would pass the
// 16 KiB of workgroup memory every device offers)
var<workgroup> b_lo: array<array<f64, 3>, 256>;
var<workgroup> b_hi: array<array<f64, 3>, 256>;

// The least and greatest (by component) of the group's `size` threads' lo and hi, into b_lo[0]
// and b_hi[0] (a tree of fixed shape; every thread of the group calls it).
fn bounds_in_group(l: u32, size: u32, lo: vec3<f64>, hi: vec3<f64>) {
    for (var k = 0u; k < 3u; k = k + 1u) {
        b_lo[l][k] = lo[k];
        b_hi[l][k] = hi[k];
    }
    workgroupBarrier();
    for (var h = size / 2u; h > 0u; h = h >> 1u) {
        if (l < h) {
            for (var k = 0u; k < 3u; k = k + 1u) {
                b_lo[l][k] = min(b_lo[l][k], b_lo[l + h][k]);
                b_hi[l][k] = max(b_hi[l][k], b_hi[l + h][k]);
            }
        }
        workgroupBarrier();
    }
}

fn group_bound(b: array<f64, 3>) -> vec3<f64> {
    return vec3<f64>(b[0], b[1], b[2]);
}

@compute @workgroup_size(256)
fn c_scan(@builtin(local_invocation_id) lid: vec3<u32>) {
    params();
    let run = !halted();
    block_offsets(C_M, lid.x, run);
    if (lid.x == 0u && run) {
        atomicStore(&grid[G_BIGN], 0u);
    }
    // the bounds of c_count's groups
    let groups = (C_NF + 63u) / 64u;
    var lo = vec3<f64>(BIG);
    var hi = vec3<f64>(-BIG);
    for (var g = lid.x; g < groups; g = g + 256u) {
        let o = FS * C_NF + BOUNDS * g;
        lo = min(lo, vec3<f64>(fsph[o], fsph[o + 1u], fsph[o + 2u]));
        hi = max(hi, vec3<f64>(fsph[o + 3u], fsph[o + 4u], fsph[o + 5u]));
    }
    bounds_in_group(lid.x, 256u, lo, hi);
    if (lid.x == 0u && run) {
        let d = max(group_bound(b_hi[0]) - group_bound(b_lo[0]), vec3<f64>(0.0lf));
        let age = atomicLoad(&grid[G_FLAGS]);
        let made = atomicLoad(&grid[G_FLAGS + 4u]) != 0u;
        var mode = CELLS;
        if (age >= WAIT && C_K > 0u) {
            mode = LISTS;
            if (!made || !(sqrt(dot(d, d)) <= cfl[CF_MU])) {
                mode = BUILD;
            }
        }
        atomicStore(&grid[G_FLAGS + 1u], mode);
        atomicStore(&grid[G_FLAGS], min(age + 1u, WAIT));
        if (mode == BUILD) {
            atomicStore(&grid[G_FLAGS + 2u], 0u);
            atomicAdd(&grid[G_FLAGS + 3u], 1u);
            atomicStore(&grid[G_FLAGS + 4u], 1u);
        }
    }
}

@compute @workgroup_size(256)
fn c_offsets(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
             @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    offsets(G_COUNT, G_OFF, G_FILL, C_M, group_index(wid, nw), lid.x, !halted());
}

@compute @workgroup_size(256)
fn c_hsums(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
           @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    block_sums(H_COUNT, C_NF, group_index(wid, nw), lid.x, !halted());
}

@compute @workgroup_size(256)
fn c_hscan(@builtin(local_invocation_id) lid: vec3<u32>) {
    params();
    let run = !halted();
    block_offsets(C_NF, lid.x, run);
    if (lid.x == 0u && run) {
        atomicStore(&grid[G_LONGN], 0u);
    }
}

@compute @workgroup_size(256)
fn c_hoffsets(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
              @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    offsets(H_COUNT, H_OFF, H_FILL, C_NF, group_index(wid, nw), lid.x, !halted());
}

// ---------------------------------------------------------------- node to face (penalty.rs)

struct Proj {
    ok: bool,
    w: vec4<f64>,
    point: vec3<f64>,
    n: vec3<f64>,
    gap: f64,
}

fn no_proj() -> Proj {
    return Proj(false, vec4<f64>(0.0lf), vec3<f64>(0.0lf), vec3<f64>(0.0lf), 0.0lf);
}

// det is NaN or at most 1e-12 j11 j22 (penalty.rs newton `singular`)
fn singular(det: f64, j11: f64, j22: f64) -> bool {
    return !(det > 1e-12lf * j11 * j22);
}

// Node s on the bilinear face p (penalty.rs project): Newton on the closest-point conditions
// from the centre; the triangles when it does not converge.
fn project(p: array<vec3<f64>, 4>, s: vec3<f64>) -> Proj {
    let a0 = coeff(p, 1.0lf, 1.0lf, 1.0lf, 1.0lf);
    let a1 = coeff(p, -1.0lf, 1.0lf, 1.0lf, -1.0lf);
    let a2 = coeff(p, -1.0lf, -1.0lf, 1.0lf, 1.0lf);
    let a3 = coeff(p, 1.0lf, -1.0lf, 1.0lf, -1.0lf);
    var xi = 0.0lf;
    var eta = 0.0lf;
    // 0 converged, 1 outside, 2 failed
    var state = 2u;
    for (var it = 0u; it < MAX_ITER; it = it + 1u) {
        let x_xi = a1 + a3 * eta;
        let x_eta = a2 + a3 * xi;
        let r = ((a0 + a1 * xi) + (a2 * eta + a3 * (xi * eta))) - s;
        let f1 = dot(r, x_xi);
        let f2 = dot(r, x_eta);
        let j11 = dot(x_xi, x_xi);
        let j22 = dot(x_eta, x_eta);
        var j12 = dot(x_xi, x_eta) + dot(r, a3);
        var det = j11 * j22 - j12 * j12;
        if (singular(det, j11, j22)) {
            j12 = dot(x_xi, x_eta);
            det = j11 * j22 - j12 * j12;
            if (singular(det, j11, j22)) {
                break;
            }
        }
        let dxi = (j22 * f1 - j12 * f2) / det;
        let deta = (j11 * f2 - j12 * f1) / det;
        xi = xi - dxi;
        eta = eta - deta;
        if (abs(dxi) + abs(deta) < NEWTON_TOL) {
            state = 0u;
            break;
        }
        if (abs(xi) > 4.0lf || abs(eta) > 4.0lf) {
            state = 1u;
            break;
        }
    }
    if (state == 1u) {
        return no_proj();
    }
    if (state == 2u) {
        return project_triangles(p, s);
    }
    let lim = 1.0lf + INSIDE_TOL;
    if (abs(xi) > lim || abs(eta) > lim) {
        return no_proj();
    }
    let x_xi = a1 + a3 * eta;
    let x_eta = a2 + a3 * xi;
    let c = cross(x_xi, x_eta);
    let len = sqrt(dot(c, c));
    if (!(len > 0.0lf)) {
        return no_proj();
    }
    let n = c * (1.0lf / len);
    let w = vec4<f64>(
        0.25lf * (1.0lf - xi) * (1.0lf - eta),
        0.25lf * (1.0lf + xi) * (1.0lf - eta),
        0.25lf * (1.0lf + xi) * (1.0lf + eta),
        0.25lf * (1.0lf - xi) * (1.0lf + eta));
    let point = (a0 + a1 * xi) + (a2 * eta + a3 * (xi * eta));
    return Proj(true, w, point, n, dot(s - point, n));
}

// The face as 4 triangles (x_a, x_a+1, centroid) (penalty.rs project_triangles).
fn project_triangles(p_in: array<vec3<f64>, 4>, s: vec3<f64>) -> Proj {
    var p = p_in;
    let c = ((p[0] + p[1]) + (p[2] + p[3])) * 0.25lf;
    var best = no_proj();
    for (var a = 0u; a < 4u; a = a + 1u) {
        let b = (a + 1u) % 4u;
        let x0 = p[a];
        let x1 = p[b];
        let nn = cross(x1 - x0, c - x0);
        let area2 = sqrt(dot(nn, nn));
        if (!(area2 > 0.0lf)) {
            continue;
        }
        let n = nn * (1.0lf / area2);
        let g = dot(s - x0, n);
        let q = s - n * g;
        let l0 = dot(cross(x1 - q, c - q), n) / area2;
        let l1 = dot(cross(c - q, x0 - q), n) / area2;
        let lc = 1.0lf - l0 - l1;
        if (l0 < -INSIDE_TOL || l1 < -INSIDE_TOL || lc < -INSIDE_TOL) {
            continue;
        }
        if (best.ok && abs(best.gap) <= abs(g)) {
            continue;
        }
        var w = vec4<f64>(0.25lf * lc);
        w[a] = w[a] + l0;
        w[b] = w[b] + l1;
        var point = vec3<f64>(0.0lf);
        for (var k = 0u; k < 4u; k = k + 1u) {
            point = point + p[k] * w[k];
        }
        best = Proj(true, w, point, n, dot(s - point, n));
    }
    return best;
}

// ---------------------------------------------------------------- detection

// The unit normal of pass-node j's surface: the sum of the diagonal cross products of its
// faces on the node side (mod.rs NodeFrame::of; zero when the sum is).
fn node_normal(j: u32) -> vec3<f64> {
    var n = vec3<f64>(0.0lf);
    for (var k = ci[CI_NFPTR + j]; k < ci[CI_NFPTR + j + 1u]; k = k + 1u) {
        let p = corners(ci[k]);
        n = n + cross(p[2] - p[0], p[3] - p[1]);
    }
    let l = sqrt(dot(n, n));
    if (l > 0.0lf) {
        return n * (1.0lf / l);
    }
    return n;
}

// The spring of the node of pass-node j against a face of stiffness k_face (PENOPT 1: the
// smaller of the two; 2: the face's; surface.rs pair_stiffness).
fn pair_k(k_face: f64, j: u32) -> f64 {
    if (cfl[CF_PEN] == 1.0lf) {
        return min(k_face, cfl[CF_KN + j]);
    }
    return k_face;
}

// friction.rs: mu = FD + (FS - FD) exp(-DC |v_t|) of definition `def`
fn mu_of(def: u32, speed: f64) -> f64 {
    let fr = CF_DEF + 4u * def;
    return cfl[fr + 1u] + (cfl[fr] - cfl[fr + 1u]) * exp64(-cfl[fr + 2u] * speed);
}

fn frictionless(def: u32) -> bool {
    return cfl[CF_DEF + 4u * def + 3u] != 0.0lf;
}

// friction.rs tangential_force: the last force turned into the plane of n, less k du_t, capped
// at f_max.
fn tangential(ft_prev: vec3<f64>, n: vec3<f64>, du_t: vec3<f64>, k: f64, f_max: f64) -> vec3<f64> {
    let mag = sqrt(dot(ft_prev, ft_prev));
    var pp = ft_prev - n * dot(ft_prev, n);
    let pm = sqrt(dot(pp, pp));
    if (pm > 0.0lf) {
        pp = pp * (mag / pm);
    } else {
        pp = vec3<f64>(0.0lf);
    }
    let trial = pp - du_t * k;
    let t = sqrt(dot(trial, trial));
    if (t > f_max) {
        var sc = 0.0lf;
        if (t > 0.0lf) {
            sc = f_max / t;
        }
        return trial * sc;
    }
    return trial;
}

// Every face of pass-node j's set lies on a tight closed crack (mod.rs Side::buried).
fn on_tight_cracks(j: u32) -> bool {
    let a = ci[CI_NFPTR + j];
    let b = ci[CI_NFPTR + j + 1u];
    if (a == b) {
        return false;
    }
    for (var k = a; k < b; k = k + 1u) {
        let c = ci[CI_FCLO + ci[k]];
        if (c == NONE || clo[CLO * c + 19u] == 0.0lf) {
            return false;
        }
    }
    return true;
}

fn hit_v(o: u32) -> vec3<f64> {
    return vec3<f64>(hits[o], hits[o + 1u], hits[o + 2u]);
}

// Pass-node j, its node n at s, against face f of the pass's face side `side`: the nearer
// contact of it and (best_f, best) (mod.rs NodeCheck::test, after the bounds that only save
// work: a face whose sphere holds no contact is skipped here too).
var<private> best_f: u32;
var<private> best: Proj;
var<private> frame_done: bool;
var<private> frame_n: vec3<f64>;
fn test_face(j: u32, n: u32, s: vec3<f64>, f: u32, side: u32) {
    if (ci[CI_FSIDE + f] != side) {
        return;
    }
    // the face's sphere, as c_count found it, before its nodes and corners are read (it
    // rejects most of a cell's faces)
    let r = fsph[FS * f + 3u];
    let depth = cfl[CF_DEPTH + f];
    if (!in_sphere(f, s, false)) {
        return;
    }
    // not a face that holds the node, a copy tied to it (one entry) or chained to it (one
    // label): mod.rs Query::run
    let label = ci[CI_PN + PN * j + 3u];
    for (var a = 0u; a < 4u; a = a + 1u) {
        if (face_node(f, a) == n || ci[CI_FLAB + 4u * f + a] == label) {
            return;
        }
    }
    var p = corners(f);
    let gap_min = GAP_TOL * r;
    let g2 = gap_min * gap_min;
    for (var a = 0u; a < 4u; a = a + 1u) {
        let e = s - p[a];
        if (!(dot(e, e) > g2)) {
            return;
        }
    }
    let pr = project(p, s);
    if (!pr.ok || !(pr.gap < -gap_min && pr.gap > -depth)) {
        return;
    }
    if (!frame_done) {
        frame_n = node_normal(j);
        frame_done = true;
    }
    if (dot(frame_n, pr.n) > -FACING) {
        return;
    }
    if (best_f == NONE || pr.gap > best.gap || (pr.gap == best.gap && f < best_f)) {
        best_f = f;
        best = pr;
    }
}

// Point s lies in face f's search sphere (as c_count found it), grown by the lists' margin
// when `grown` (reach_of).
fn in_sphere(f: u32, s: vec3<f64>, grown: bool) -> bool {
    let ds = s - vec3<f64>(fsph[FS * f], fsph[FS * f + 1u], fsph[FS * f + 2u]);
    let reach = reach_of(f, fsph[FS * f + 3u], grown);
    // (a sphere of no finite size holds the point: the tests after it reject such a face)
    return !(dot(ds, ds) > reach * reach);
}

// Face f may touch node n at s in a pass against face side `side`: on that side, not holding
// the node, its sphere (grown when `grown`) holding it.
fn candidate(n: u32, s: vec3<f64>, f: u32, side: u32, grown: bool) -> bool {
    if (ci[CI_FSIDE + f] != side) {
        return false;
    }
    for (var a = 0u; a < 4u; a = a + 1u) {
        if (face_node(f, a) == n) {
            return false;
        }
    }
    return in_sphere(f, s, grown);
}

// The k-th face a node reads from the grid: of its cell (in_cell faces from `at` in the cells'
// entries), then of the list every node reads.
fn cell_face(at: u32, in_cell: u32, k: u32) -> u32 {
    if (k < in_cell) {
        return atomicLoad(&grid[G_ENT + at + k]);
    }
    return atomicLoad(&grid[G_BIG + k - in_cell]);
}

// Face f on pass-node j's list (its node n at s, the pass's face side `side`; c_scan) when
// it is on that side, does not hold the node and its grown sphere holds it; past C_K faces the
// node is counted only, and checked against its cell (G_FLAGS + 2).
fn enlist(j: u32, n: u32, s: vec3<f64>, f: u32, side: u32) {
    if (!candidate(n, s, f, side, true)) {
        return;
    }
    let k = atomicAdd(&grid[G_CANDN + j], 1u);
    if (k < C_K) {
        atomicStore(&grid[G_CAND + CANDS * j + k], f);
    } else {
        atomicStore(&grid[G_FLAGS + 2u], 1u);
    }
}

// For tests (C_VERIFY): every face of pass-node j's cell and of the big list whose search
// sphere holds the node, on its side and not holding it, must be on its list (G_FLAGS + 5
// counts those that are not, + 6 those looked for).
fn verify(j: u32, n: u32, s: vec3<f64>, side: u32, lane: u32, lanes: u32) {
    let b = hash(cell_of(s));
    let at = atomicLoad(&grid[G_OFF + b]);
    let in_cell = atomicLoad(&grid[G_OFF + b + 1u]) - at;
    let total = in_cell + atomicLoad(&grid[G_BIGN]);
    let listed = atomicLoad(&grid[G_CANDN + j]);
    for (var k = lane; k < total; k = k + lanes) {
        let f = cell_face(at, in_cell, k);
        if (!candidate(n, s, f, side, false)) {
            continue;
        }
        atomicAdd(&grid[G_FLAGS + 6u], 1u);
        var found = false;
        for (var i = 0u; i < listed; i = i + 1u) {
            found = found || atomicLoad(&grid[G_CAND + CANDS * j + i]) == f;
        }
        if (!found) {
            atomicAdd(&grid[G_FLAGS + 5u], 1u);
        }
    }
}

// the room of a pass-node's list (contact_tables.rs CANDS; C_K at most this)
const CANDS: u32 = 64u;

// The lanes that check one pass-node (c_detect; C_LANES of them, a power of two up to 64:
// contact_tables.rs Tuning): each tests every C_LANES-th face of the cell
// and of the `big` list, and the lanes' nearest contacts are then compared. The nearest is
// the greatest in one total order (the least penetration, of equal ones the lowest face), so
// which lane tested a face does not change the one that wins: the result is the one thread's
// of a pass-node, bit for bit, with the longest chain of a thread's loads C_LANES times shorter
// (on an H100 the one-thread pass waited on its loads: 64% of the 2800 ball's step).
var<workgroup> d_gap: array<f64, 64>;
var<workgroup> d_face: array<u32, 64>;

@compute @workgroup_size(64)
fn c_detect(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
            @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    halves();
    let t = pass_index(wid, nw, lid.x);
    let lanes = C_LANES;
    let j = t / lanes;
    let lane = lid.x % lanes;
    let live = j < C_NP && !halted();
    best_f = NONE;
    frame_done = false;
    var n = 0u;
    var def = 0u;
    // the lists made again in this step: each one emptied first
    let mode = atomicLoad(&grid[G_FLAGS + 1u]);
    let build = mode == BUILD;
    if (live && build && lane == 0u) {
        atomicStore(&grid[G_CANDN + j], 0u);
    }
    // (the node's lanes are in this group: 64 is a multiple of C_LANES; a storage barrier,
    // the count being in storage)
    storageBarrier();
    if (live) {
        n = ci[CI_PN + PN * j];
        let q = ci[CI_PN + PN * j + 1u];
        // a node all of whose faces eroded, or lie on tight closed cracks, is buried: not
        // checked (mod.rs Side::buried)
        let buried = ci[CI_PN + PN * j + 2u] != 0u || (C_NC > 0u && on_tight_cracks(j));
        let side = ci[CI_PASS + 2u * q];
        def = ci[CI_PASS + 2u * q + 1u];
        let s = pos(n);
        // the node against its list, or every face of its cell and the big ones: when the
        // lists are not in use, for a node with more candidates than its list holds, and when
        // the lists are made (then listed too, the buried nodes' with the others)
        let listed = atomicLoad(&grid[G_CANDN + j]);
        let use_list = mode == LISTS && listed <= C_K;
        var at = 0u;
        var in_cell = 0u;
        var total = listed;
        if (!use_list) {
            let b = hash(cell_of(s));
            at = atomicLoad(&grid[G_OFF + b]);
            in_cell = atomicLoad(&grid[G_OFF + b + 1u]) - at;
            total = in_cell + atomicLoad(&grid[G_BIGN]);
        }
        if (!finite3(s) || (buried && !build)) {
            total = 0u;
        }
        for (var k = lane; k < total; k = k + lanes) {
            var f: u32;
            if (use_list) {
                f = atomicLoad(&grid[G_CAND + CANDS * j + k]);
            } else {
                f = cell_face(at, in_cell, k);
            }
            if (build) {
                enlist(j, n, s, f, side);
            }
            if (!buried) {
                test_face(j, n, s, f, side);
            }
        }
        if (C_VERIFY != 0u && use_list && finite3(s)) {
            verify(j, n, s, side, lane, lanes);
        }
    }
    // the nearest of the pass-node's lanes (of a face tested twice, in two cells that hash
    // alike, the lower lane's): that lane goes on, or the first when none found one
    d_gap[lid.x] = best.gap;
    d_face[lid.x] = best_f;
    workgroupBarrier();
    let first = lid.x - lane;
    var win = 0u;
    for (var i = 1u; i < lanes; i = i + 1u) {
        let f = d_face[first + i];
        let w = d_face[first + win];
        let g = d_gap[first + i];
        let gw = d_gap[first + win];
        if (f != NONE && (w == NONE || g > gw || (g == gw && f < w))) {
            win = i;
        }
    }
    if (!live || lane != win) {
        return;
    }
    let o = HIT * j;
    let prev_face = hits[o];
    if (best_f == NONE) {
        // out of contact: the hit and the tangential force start again from zero
        for (var k = 0u; k < HIT; k = k + 1u) {
            hits[o + k] = 0.0lf;
        }
        hits[o] = -1.0lf;
        return;
    }
    let fi = best_f;
    let pr = best;
    let dt_prev = cf[DT_PREV];
    let v = vel(n);
    var v_face = vec3<f64>(0.0lf);
    for (var a = 0u; a < 4u; a = a + 1u) {
        v_face = v_face + vel(face_node(fi, a)) * pr.w[a];
    }
    let v_rel = v - v_face;
    // the first step has no motion to explain a penetration (engagement.rs): in full
    var approach = BIG;
    if (dt_prev > 0.0lf) {
        approach = max(-dot(v_rel, pr.n), 0.0lf) * dt_prev;
    }
    let k = pair_k(cfl[CF_K + fi], j);
    let gap = pr.gap;
    // engagement.rs engage
    var engaged = 0.0lf;
    if (prev_face < 0.0lf) {
        engaged = max(gap, -approach);
    } else if (u32(prev_face) == fi) {
        engaged = gap - max(hits[o + 9u], gap);
    } else {
        let k_prev = pair_k(cfl[CF_K + u32(prev_face)], j);
        var carried = 0.0lf;
        if (k > 0.0lf) {
            carried = hits[o + 8u] * sqrt(k_prev / k);
        }
        engaged = max(gap, carried - approach);
    }
    engaged = min(engaged, 0.0lf);
    let offset = gap - engaged;
    // penalty.rs normal_force
    var f_n = vec3<f64>(0.0lf);
    if (engaged < 0.0lf) {
        f_n = pr.n * (-k * engaged);
    }
    let fn_mag = -k * engaged;
    var f_t = vec3<f64>(0.0lf);
    let fr = CF_DEF + 4u * def;
    if (cfl[fr + 3u] == 0.0lf && fn_mag > 0.0lf) {
        // friction.rs: mu = FD + (FS - FD) exp(-DC |v_t|), the elastic trial force capped
        let v_t = v_rel - pr.n * dot(v_rel, pr.n);
        let speed = sqrt(dot(v_t, v_t));
        f_t = tangential(hit_v(o + 11u), pr.n, v_t * dt_prev, k, mu_of(def, speed) * fn_mag);
    }
    let f = f_n + f_t;
    hits[o] = f64(fi);
    for (var a = 0u; a < 4u; a = a + 1u) {
        hits[o + 1u + a] = pr.w[a];
    }
    for (var i = 0u; i < 3u; i = i + 1u) {
        hits[o + 5u + i] = f[i];
        hits[o + 11u + i] = f_t[i];
    }
    hits[o + 8u] = engaged;
    hits[o + 9u] = offset;
    hits[o + 10u] = fn_mag;
    if (fn_mag != 0.0lf) {
        atomicAdd(&grid[H_COUNT + fi], 1u);
    }
}

// The nodes that push on each face, listed by face (in any order: the gather orders them).
@compute @workgroup_size(64)
fn c_hfill(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
           @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    let j = pass_index(wid, nw, lid.x);
    if (j >= C_NP || halted()) {
        return;
    }
    let o = HIT * j;
    if (hits[o] < 0.0lf || hits[o + 10u] == 0.0lf) {
        return;
    }
    let f = u32(hits[o]);
    var at = atomicLoad(&grid[H_OFF + f]) + atomicAdd(&grid[H_FILL + f], 1u);
    if (C_REVERSE != 0u) {
        // (for tests: from the list's end)
        at = atomicLoad(&grid[H_OFF + f + 1u]) - 1u - (at - atomicLoad(&grid[H_OFF + f]));
    }
    atomicStore(&grid[H_LIST + at], j);
}

// ---------------------------------------------------------------- gather and energy

// The reactions on each face's corners: -w_a f of each pass-node that pushes on it (w_a the
// weight of corner a at its contact point), added in pass-node order, so that the sums do not
// depend on the order c_hfill listed them in. A list of at most SHORT is sorted and added by
// one thread (c_hsort); a longer one (the faces of a coarse plate under a fine ball: hundreds)
// goes to the `long` list, and a group of 64 sorts it and adds it (c_hlong), since one thread
// waiting on its loads one after another was most of the step on an H100.
const SHORT: u32 = 16u;
// the longest list a group sorts in its own memory (longer ones: in place, by one thread)
const LONG_MAX: u32 = 1024u;

fn list_at(k: u32) -> u32 {
    return atomicLoad(&grid[H_LIST + k]);
}

// The reactions of pass-node j on the corners of the face it pushes on, added to r.
fn add_reactions(r: ptr<function, array<vec3<f64>, 4>>, j: u32) {
    let o = HIT * j;
    let fj = hit_v(o + 5u);
    for (var a = 0u; a < 4u; a = a + 1u) {
        (*r)[a] = (*r)[a] + fj * (-hits[o + 1u + a]);
    }
}

fn put_reactions(f: u32, r: array<vec3<f64>, 4>) {
    for (var a = 0u; a < 4u; a = a + 1u) {
        for (var i = 0u; i < 3u; i = i + 1u) {
            fsph[FS * f + 4u + 3u * a + i] = r[a][i];
        }
    }
}

@compute @workgroup_size(64)
fn c_hsort(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
           @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    let f = pass_index(wid, nw, lid.x);
    if (f >= C_NF || halted()) {
        return;
    }
    let base = atomicLoad(&grid[H_OFF + f]);
    let n = atomicLoad(&grid[H_OFF + f + 1u]) - base;
    if (n == 0u) {
        return;
    }
    if (n > min(C_SHORT, SHORT)) {
        let k = atomicAdd(&grid[G_LONGN], 1u);
        atomicStore(&grid[G_LONG + k], f);
        return;
    }
    // an insertion sort of the few
    var l: array<u32, SHORT>;
    for (var i = 0u; i < n; i = i + 1u) {
        let v = list_at(base + i);
        var k = i;
        while (k > 0u && l[k - 1u] > v) {
            l[k] = l[k - 1u];
            k = k - 1u;
        }
        l[k] = v;
    }
    var r: array<vec3<f64>, 4>;
    for (var i = 0u; i < n; i = i + 1u) {
        add_reactions(&r, l[i]);
    }
    put_reactions(f, r);
}

// A face's list of more than LONG_MAX nodes, sorted in place (a heap sort by one thread).
fn sift(base: u32, start: u32, n: u32) {
    var r = start;
    loop {
        let c = 2u * r + 1u;
        if (c >= n) {
            break;
        }
        var m = c;
        if (c + 1u < n && list_at(base + c + 1u) > list_at(base + c)) {
            m = c + 1u;
        }
        let vr = list_at(base + r);
        let vm = list_at(base + m);
        if (vm <= vr) {
            break;
        }
        atomicStore(&grid[H_LIST + base + r], vm);
        atomicStore(&grid[H_LIST + base + m], vr);
        r = m;
    }
}

fn heap_sort(base: u32, n: u32) {
    for (var s = n / 2u; s > 0u; s = s - 1u) {
        sift(base, s - 1u, n);
    }
    for (var e = n - 1u; e > 0u; e = e - 1u) {
        let top = list_at(base);
        atomicStore(&grid[H_LIST + base], list_at(base + e));
        atomicStore(&grid[H_LIST + base + e], top);
        sift(base, 0u, e);
    }
}

var<workgroup> h_list: array<u32, LONG_MAX>;
var<workgroup> h_sum: array<vec3<f64>, 256>;
var<workgroup> h_at: u32;

// The long lists, by a fixed number of groups, each taking every so many: the list sorted (a
// bitonic sort in the group's memory), each of the 64 threads adding a run of it in order,
// the runs' sums added by a tree of fixed shape.
@compute @workgroup_size(64)
fn c_hlong(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
           @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    let l = lid.x;
    if (l == 0u) {
        h_at = select(atomicLoad(&grid[G_LONGN]), 0u, halted());
    }
    let count = workgroupUniformLoad(&h_at);
    let groups = nw.x * nw.y;
    for (var i = wid.y * nw.x + wid.x; i < count; i = i + groups) {
        if (l == 0u) {
            h_at = atomicLoad(&grid[G_LONG + i]);
        }
        let f = workgroupUniformLoad(&h_at);
        let base = atomicLoad(&grid[H_OFF + f]);
        if (l == 0u) {
            h_at = atomicLoad(&grid[H_OFF + f + 1u]) - base;
        }
        let n = workgroupUniformLoad(&h_at);
        if (l == 0u) {
            h_at = u32(n <= min(C_LONG, LONG_MAX));
        }
        let in_group = workgroupUniformLoad(&h_at) != 0u;
        if (in_group) {
            var p = 1u;
            while (p < n) {
                p = p << 1u;
            }
            for (var k = l; k < p; k = k + 64u) {
                var v = NONE;
                if (k < n) {
                    v = list_at(base + k);
                }
                h_list[k] = v;
            }
            workgroupBarrier();
            for (var k = 2u; k <= p; k = k << 1u) {
                for (var d = k >> 1u; d > 0u; d = d >> 1u) {
                    for (var a = l; a < p; a = a + 64u) {
                        let b = a ^ d;
                        if (b > a) {
                            let x = h_list[a];
                            let y = h_list[b];
                            if ((x > y) == ((a & k) == 0u)) {
                                h_list[a] = y;
                                h_list[b] = x;
                            }
                        }
                    }
                    workgroupBarrier();
                }
            }
        } else {
            if (l == 0u) {
                heap_sort(base, n);
            }
            storageBarrier();
            workgroupBarrier();
        }
        let run = (n + 63u) / 64u;
        var r: array<vec3<f64>, 4>;
        for (var k = l * run; k < min(n, (l + 1u) * run); k = k + 1u) {
            var j = 0u;
            if (in_group) {
                j = h_list[k];
            } else {
                j = list_at(base + k);
            }
            add_reactions(&r, j);
        }
        for (var a = 0u; a < 4u; a = a + 1u) {
            h_sum[4u * l + a] = r[a];
        }
        workgroupBarrier();
        for (var s = 32u; s > 0u; s = s >> 1u) {
            if (l < s) {
                for (var a = 0u; a < 4u; a = a + 1u) {
                    h_sum[4u * l + a] = h_sum[4u * l + a] + h_sum[4u * (l + s) + a];
                }
            }
            workgroupBarrier();
        }
        if (l == 0u) {
            for (var a = 0u; a < 4u; a = a + 1u) {
                r[a] = h_sum[a];
            }
            put_reactions(f, r);
        }
        workgroupBarrier();
    }
}

var<workgroup> g_s: array<f64, 256>;

// Surface node g's contact force: the closed cracks' pairs at it, then the forces of its own
// pass-nodes (in pass-node order; one with no force adds nothing), then the reactions on the
// faces it holds, face by face in the tables' order (each face's sum of c_hsort or c_hlong).
// The CPU adds the same terms in the order of the pass-nodes that make them (mod.rs
// Contact::compute, scatter_closures then scatter_pairs): the sums agree to rounding, and
// each is in an order of its own that does not change from run to run.
fn gather(g: u32) -> vec3<f64> {
    var f = vec3<f64>(0.0lf);
    // first the closed cracks' pairs at the node, in the order the cracks closed: the force
    // on b_k, its opposite on a_k (mod.rs scatter_closures)
    for (var k = ci[CI_GCPTR + g]; k < ci[CI_GCPTR + g + 1u]; k = k + 1u) {
        let e = ci[k];
        let c = e >> 3u;
        let p = (e >> 1u) & 3u;
        let o = CLO * c;
        let fn_mag = clo[o + 15u + p];
        if (fn_mag > 0.0lf) {
            var fk = vec3<f64>(clo[o + 12u], clo[o + 13u], clo[o + 14u]) * fn_mag;
            if (!frictionless(ci[CI_CLO + 9u * c + 8u])) {
                fk = fk + vec3<f64>(clo[o + 3u * p], clo[o + 3u * p + 1u], clo[o + 3u * p + 2u]);
            }
            if ((e & 1u) != 0u) {
                f = f + fk * (-1.0lf);
            } else {
                f = f + fk;
            }
        }
    }
    for (var k = ci[CI_GOPTR + g]; k < ci[CI_GOPTR + g + 1u]; k = k + 1u) {
        let o = HIT * ci[k];
        if (hits[o + 10u] != 0.0lf) {
            f = f + hit_v(o + 5u);
        }
    }
    for (var k = ci[CI_GFPTR + g]; k < ci[CI_GFPTR + g + 1u]; k = k + 1u) {
        let face = ci[k] >> 2u;
        if (atomicLoad(&grid[H_OFF + face + 1u]) > atomicLoad(&grid[H_OFF + face])) {
            let o = FS * face + 4u + 3u * (ci[k] & 3u);
            f = f + vec3<f64>(fsph[o], fsph[o + 1u], fsph[o + 2u]);
        }
    }
    return f;
}

// Each surface node's contact force into `fcon`, and the work over the last step of the last
// step's force and this step's (partials per group).
@compute @workgroup_size(64)
fn c_gather(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>,
            @builtin(num_workgroups) nw: vec3<u32>) {
    params();
    let g = pass_index(wid, nw, lid.x);
    let l = lid.x;
    var work = 0.0lf;
    if (g < C_NG && !halted()) {
        let n = ci[CI_GN + g];
        let f = gather(g);
        for (var i = 0u; i < 3u; i = i + 1u) {
            fcon[3u * n + i] = f[i];
        }
        let v = vel(n);
        let fp = vec3<f64>(fprev[3u * g], fprev[3u * g + 1u], fprev[3u * g + 2u]);
        work = dot(fp, v) + dot(f, v);
        for (var i = 0u; i < 3u; i = i + 1u) {
            fprev[3u * g + i] = f[i];
        }
    }
    // the group's sum, by a tree of fixed shape
    g_s[l] = work;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s = s >> 1u) {
        if (l < s) {
            g_s[l] = g_s[l] + g_s[l + s];
        }
        workgroupBarrier();
    }
    let group = wid.y * nw.x + wid.x;
    if (l == 0u && group < C_GG) {
        cpart[group] = g_s[0];
    }
}

// The contact energy of the step: dE = -1/2 dt^(n-1/2) sum (f^(n-1) + f^n).v^(n-1/2)
// (mod.rs, Energy), the groups' partials added l, l + 256, ... by each thread, then by a tree.
@compute @workgroup_size(256)
fn c_energy(@builtin(local_invocation_id) lid: vec3<u32>) {
    params();
    let l = lid.x;
    let run = !halted();
    var acc = 0.0lf;
    if (run) {
        for (var k = l; k < C_GG; k = k + 256u) {
            acc = acc + cpart[k];
        }
    }
    g_s[l] = acc;
    workgroupBarrier();
    for (var s = 128u; s > 0u; s = s >> 1u) {
        if (l < s) {
            g_s[l] = g_s[l] + g_s[l + s];
        }
        workgroupBarrier();
    }
    if (l == 0u && run) {
        cf[E_CONTACT] = cf[E_CONTACT] - 0.5lf * cf[DT_PREV] * g_s[0];
    }
}
