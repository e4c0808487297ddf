//! The model: everything about a run that does not change while it runs.
//!
//! Built once by the deck reader (`cleave-io`) or by the mesh generators in [`crate::mesh`],
//! validated there, then consumed read-only by the solver. Node and element references are
//! dense internal indices (`u32`); deck ids live only in `node_ids`, `elem_ids` and the `id`
//! fields, for output and messages.

use crate::curve::Curve;
use crate::math::{Mat3, Vec3};
pub use crate::per_node::PerNode;

/// A complete model.
#[derive(Clone, Debug, Default)]
pub struct Model {
    pub title: String,
    /// Deck id of each node (a split model's copies share their deck node's: [`PerNode`]).
    pub node_ids: PerNode<i64>,
    /// Reference (initial) coordinates of each node.
    pub x0: PerNode<Vec3>,
    /// Initial velocity of each node (from `*INITIAL_VELOCITY_*`, resolved by the builder).
    pub v0: PerNode<Vec3>,
    /// Deck id of each element.
    pub elem_ids: Vec<i64>,
    /// Part index (into `parts`) of each element.
    pub elem_part: Vec<u32>,
    /// Connectivity: 8 node indices per element, LS-DYNA corner order; wedges and tetrahedra
    /// in the degenerate layouts of [`crate::element::shape`].
    pub conn: Vec<[u32; 8]>,
    pub parts: Vec<Part>,
    pub sections: Vec<Section>,
    pub materials: Vec<Material>,
    pub curves: Vec<Curve>,
    pub node_sets: Vec<NodeSet>,
    pub part_sets: Vec<PartSet>,
    pub segment_sets: Vec<SegmentSet>,
    /// `*SET_SOLID` and its `_GENERATE` forms: element sets.
    pub solid_sets: Vec<SolidSet>,
    /// `*CONSTRAINED_NODAL_RIGID_BODY`: rigid bodies made of nodes.
    pub nodal_rigid: Vec<NodalRigidBody>,
    /// `*CONSTRAINED_EXTRA_NODES_NODE` / `_SET`: nodes joined to rigid parts, one entry a card.
    pub extra_nodes: Vec<ExtraNodes>,
    /// `*PART_INERTIA`: rigid parts whose mass, centre, inertia and initial velocity are given.
    pub part_inertia: Vec<PartInertia>,
    /// Single-point constraints, one entry per constrained node (sets expanded, repeated
    /// constraints on a node merged by OR).
    pub spcs: Vec<Spc>,
    pub prescribed: Vec<PrescribedMotion>,
    pub body_loads: Vec<BodyLoad>,
    /// `*LOAD_NODE_POINT` / `_SET`, one entry per node (sets expanded).
    pub node_loads: Vec<NodeLoad>,
    /// `*LOAD_SEGMENT` / `_SET`, one entry per segment.
    pub pressure_loads: Vec<PressureLoad>,
    pub rigid_walls: Vec<RigidWall>,
    pub contacts: Vec<ContactDef>,
    /// Tied contacts (`*CONTACT_TIED_...`, [`crate::tied`]).
    pub tied: Vec<TiedDef>,
    pub separations: Vec<SeparationDef>,
    /// Element erosion per material (`*MAT_024` FAIL, `*MAT_003` FS, `*MAT_ADD_EROSION`).
    pub erosion: Vec<crate::erosion::ErosionDef>,
    /// `*HOURGLASS` definitions (the parts' HGID).
    pub hourglass: Vec<HourglassDef>,
    pub control: Control,
    pub output: OutputRequests,
}

/// `*PART`.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    pub id: i64,
    pub title: String,
    /// Index into `Model::sections`.
    pub section: usize,
    /// Index into `Model::materials`.
    pub material: usize,
    /// Index into `Model::hourglass` (`*HOURGLASS`, the part's HGID); `None`: the
    /// `*CONTROL_HOURGLASS` and `*CONTROL_BULK_VISCOSITY` values.
    pub hourglass: Option<usize>,
}

/// `*HOURGLASS`: hourglass control and bulk viscosity of the parts that name it (HGID).
#[derive(Clone, Debug, PartialEq)]
pub struct HourglassDef {
    pub id: i64,
    /// IHQ (blank or 0: the one of `*CONTROL_HOURGLASS`).
    pub hourglass: Hourglass,
    /// QM (blank: 0.1).
    pub qh: f64,
    /// Q1, Q2: the bulk viscosity (blank: 1.5, 0.06, LS-DYNA's defaults on this card).
    pub q1: f64,
    pub q2: f64,
}

/// `*SECTION_SOLID`.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    pub id: i64,
    /// Element formulation: 1 (one-point hexahedron with hourglass control; wedges run it on
    /// their degenerate corners, tetrahedra run the one-point tetrahedron), 2 (fully integrated
    /// selectively reduced hexahedron, [`crate::element::sri`]; hexahedra only), 10 (one-point
    /// tetrahedron; tetrahedra only) or 13 (tetrahedron with nodal pressure averaging,
    /// [`crate::element::nodal_pressure`]; tetrahedra only, not in a separation group). See
    /// [`crate::element::Shape`].
    pub elform: i32,
}

/// A material card. Common parameters are fields; the law's own are in `kind`.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub id: i64,
    /// Mass density RO (kg/m^3 in SI).
    pub density: f64,
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio PR, in (-1, 0.5).
    pub poisson: f64,
    pub kind: MaterialKind,
}

impl Material {
    /// Shear modulus G = E / (2 (1 + nu)).
    pub fn shear_modulus(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }
    /// Bulk modulus K = E / (3 (1 - 2 nu)).
    pub fn bulk_modulus(&self) -> f64 {
        self.young / (3.0 * (1.0 - 2.0 * self.poisson))
    }
    /// Lame's first parameter lambda = E nu / ((1 + nu)(1 - 2 nu)).
    pub fn lame_lambda(&self) -> f64 {
        self.young * self.poisson / ((1.0 + self.poisson) * (1.0 - 2.0 * self.poisson))
    }
    /// Dilatational (P-wave) speed c = sqrt((lambda + 2G) / rho), used for the time step.
    pub fn wave_speed(&self) -> f64 {
        ((self.lame_lambda() + 2.0 * self.shear_modulus()) / self.density).sqrt()
    }
}

/// The constitutive law of a material.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialKind {
    /// `*MAT_ELASTIC` (`*MAT_001`): isotropic linear elastic (hypoelastic, Jaumann rate).
    Elastic,
    /// `*MAT_PLASTIC_KINEMATIC` (`*MAT_003`): bilinear elastic-plastic, von Mises yield,
    /// hardening mixed between kinematic (BETA = 0) and isotropic (BETA = 1).
    PlasticKinematic { sigy: f64, etan: f64, beta: f64 },
    /// `*MAT_RIGID` (`*MAT_020`). With `cmo = 1` the constraints are global:
    /// `con1` translations, `con2` rotations, each coded 0 none, 1 x, 2 y, 3 z, 4 x+y,
    /// 5 y+z, 6 z+x, 7 all. `cmo = 0`: no constraints.
    Rigid { cmo: i32, con1: i32, con2: i32 },
    /// `*MAT_JOHNSON_COOK` (`*MAT_015`) and `*MAT_SIMPLIFIED_JOHNSON_COOK` (`*MAT_098`):
    /// Johnson-Cook plasticity with rate and thermal softening
    /// ([`crate::material::JohnsonCook`]).
    JohnsonCook(crate::material::JohnsonCook),
    /// `*MAT_PIECEWISE_LINEAR_PLASTICITY` (`*MAT_024`): a hardening curve with
    /// Cowper-Symonds rate scaling ([`crate::material::PiecewiseLinear`]).
    PiecewiseLinear(crate::material::PiecewiseLinear),
}

/// A node set; members are node indices.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeSet {
    pub id: i64,
    pub nodes: Vec<u32>,
}

/// A part set; members are part indices.
#[derive(Clone, Debug, PartialEq)]
pub struct PartSet {
    pub id: i64,
    pub parts: Vec<usize>,
}

/// A segment set; each segment is 4 node indices (a triangle repeats its third node).
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentSet {
    pub id: i64,
    pub segments: Vec<[u32; 4]>,
}

/// An element set (`*SET_SOLID`); members are element indices.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidSet {
    pub id: i64,
    pub elems: Vec<u32>,
}

/// Mass properties and initial motion given on a card (`*PART_INERTIA`, the `_INERTIA` option
/// of `*CONSTRAINED_NODAL_RIGID_BODY`) instead of computed from the body's nodal masses.
#[derive(Clone, Debug, PartialEq)]
pub struct GivenInertia {
    /// Centre of mass (XC, YC, ZC, or the coordinates of NODEID).
    pub centre: Vec3,
    /// Translational mass TM (> 0).
    pub mass: f64,
    /// Inertia tensor about `centre`, global axes (symmetric positive definite; IXY is the
    /// tensor's xy component).
    pub inertia: Mat3,
    /// Initial velocity of the centre (VTX, VTY, VTZ) and angular velocity (VRX, VRY, VRZ).
    pub velocity: Vec3,
    pub omega: Vec3,
}

/// `*CONSTRAINED_NODAL_RIGID_BODY`: the nodes of a node set move as one rigid body, with the
/// mass and inertia of their lumped masses (or the given ones, `_INERTIA`).
#[derive(Clone, Debug, PartialEq)]
pub struct NodalRigidBody {
    /// PID, the body's id (0: none); `*BOUNDARY_PRESCRIBED_MOTION_RIGID` may name it.
    pub id: i64,
    /// Index into `Model::node_sets` (NSID).
    pub set: usize,
    /// `_SPC`: CMO, CON1, CON2 as on `*MAT_RIGID` (0, 0, 0 without it).
    pub cmo: i32,
    pub con1: i32,
    pub con2: i32,
    /// `_INERTIA`: the body's mass properties and initial motion.
    pub inertia: Option<GivenInertia>,
}

/// `*CONSTRAINED_EXTRA_NODES_NODE` (one node) or `_SET` (a node set): nodes that move with
/// rigid part `part`, their lumped mass added to it.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtraNodes {
    /// Part index (a rigid part).
    pub part: usize,
    /// The node set (`_SET`), by index, or `None` (`_NODE`).
    pub set: Option<usize>,
    /// The nodes (the set's members for `_SET`).
    pub nodes: Vec<u32>,
    /// IFLAG 1: with `*PART_INERTIA` on the part, the extra nodes' masses are added to the
    /// given ones; 0 (LS-DYNA's default): the given properties are taken to hold them.
    pub iflag: bool,
}

/// `*PART_INERTIA` on a rigid part (index `part`).
#[derive(Clone, Debug, PartialEq)]
pub struct PartInertia {
    pub part: usize,
    pub given: GivenInertia,
}

/// The translations (or rotations) x, y, z that an LS-DYNA constraint code fixes:
/// 0 none, 1 x, 2 y, 3 z, 4 x+y, 5 y+z, 6 z+x, 7 all (`*NODE` TC/RC, `*MAT_RIGID` CON1/CON2).
pub fn dof_code(code: i32) -> [bool; 3] {
    match code {
        1 => [true, false, false],
        2 => [false, true, false],
        3 => [false, false, true],
        4 => [true, true, false],
        5 => [false, true, true],
        6 => [true, false, true],
        7 => [true, true, true],
        _ => [false; 3],
    }
}

/// A single-point constraint: `dof[0..3]` translations x, y, z; `dof[3..6]` rotations
/// (carried for completeness; solid nodes have no rotational dofs).
#[derive(Clone, Debug, PartialEq)]
pub struct Spc {
    pub node: u32,
    pub dof: [bool; 6],
}

/// What a prescribed motion acts on.
#[derive(Clone, Debug, PartialEq)]
pub enum MotionTarget {
    Node(u32),
    /// A rigid part, by part index.
    Rigid(usize),
    /// A nodal rigid body, by index into `Model::nodal_rigid`.
    NodalRigid(usize),
}

/// Whether a prescribed motion curve gives velocity or displacement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vad {
    /// VAD = 0.
    Velocity,
    /// VAD = 2.
    Displacement,
}

/// The degree of freedom a prescribed motion drives (`*BOUNDARY_PRESCRIBED_MOTION_...` DOF).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MotionDof {
    /// DOF 1, 2, 3: translation along global x, y, z (0, 1, 2).
    Axis(usize),
    /// DOF 4 and -4: translation along the unit vector `dir` (`*DEFINE_VECTOR` VID); the
    /// motion normal to it stays free (4) or is held at zero (-4, `only`).
    Along { dir: Vec3, only: bool },
    /// DOF 5, 6, 7 (about global x, y, z) and 8, -8 (about VID): the angular velocity of a
    /// rigid body about the unit vector `dir` through its centre of mass; the other components
    /// stay free (5-8) or are held at zero (-8, `only`). Nodes of solids have no rotations.
    Rotation { dir: Vec3, only: bool },
}

impl MotionDof {
    /// The component of a velocity (or of a position, or of an angular velocity) that the
    /// motion prescribes.
    pub fn component(&self, v: Vec3) -> f64 {
        match *self {
            MotionDof::Axis(a) => v[a],
            MotionDof::Along { dir, .. } | MotionDof::Rotation { dir, .. } => {
                v[0] * dir[0] + v[1] * dir[1] + v[2] * dir[2]
            }
        }
    }

    /// `v` with its prescribed component set to `s`: `v + (s - v.d) d`, or `s d` when the
    /// rest is held at zero.
    pub fn apply(&self, v: Vec3, s: f64) -> Vec3 {
        match *self {
            MotionDof::Axis(a) => {
                let mut w = v;
                w[a] = s;
                w
            }
            MotionDof::Along { dir, only } | MotionDof::Rotation { dir, only } => {
                let c = if only { 0.0 } else { s - self.component(v) };
                let base = if only { [0.0; 3] } else { v };
                let k = if only { s } else { c };
                [
                    base[0] + k * dir[0],
                    base[1] + k * dir[1],
                    base[2] + k * dir[2],
                ]
            }
        }
    }

    /// Whether it drives a rotation (rigid bodies only).
    pub fn is_rotation(&self) -> bool {
        matches!(self, MotionDof::Rotation { .. })
    }
}

/// When a prescribed motion acts (BIRTH and DEATH): from `birth` (inclusive) until `death`
/// (exclusive), judged at the middle of each step (where the velocity it sets applies); before
/// and after, its node or body moves freely.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    pub birth: f64,
    pub death: f64,
}

impl Window {
    /// From the start on, for good (LS-DYNA's defaults, BIRTH 0 and DEATH 1e28).
    pub const ALWAYS: Window = Window {
        birth: 0.0,
        death: f64::INFINITY,
    };

    /// Whether the motion acts at (mid-step) time `t`.
    pub fn holds(&self, t: f64) -> bool {
        t >= self.birth && t < self.death
    }
}

/// `*BOUNDARY_PRESCRIBED_MOTION_{NODE,SET,RIGID}` (sets expanded to one entry per node).
#[derive(Clone, Debug, PartialEq)]
pub struct PrescribedMotion {
    /// When it acts.
    pub window: Window,
    pub target: MotionTarget,
    /// The degree of freedom (deck DOF and VID).
    pub dof: MotionDof,
    pub vad: Vad,
    /// Index into `Model::curves`.
    pub curve: usize,
    /// Scale factor SF applied to the curve's ordinate.
    pub sf: f64,
}

/// `*LOAD_BODY_{X,Y,Z}`: a base acceleration; the body feels `-sf * curve(t)` along `axis`
/// (so gravity along -z is `*LOAD_BODY_Z` with +9.81).
#[derive(Clone, Debug, PartialEq)]
pub struct BodyLoad {
    pub axis: usize,
    /// Index into `Model::curves`; `None` (LCID 0) means a constant 1.
    pub curve: Option<usize>,
    pub sf: f64,
}

impl BodyLoad {
    /// The acceleration the body load imposes at time `t` (along `axis`).
    pub fn acceleration(&self, curves: &[Curve], t: f64) -> f64 {
        let c = self.curve.map_or(1.0, |i| curves[i].eval(t));
        -self.sf * c
    }
}

/// `*LOAD_NODE_POINT` / `*LOAD_NODE_SET` with DOF 1-3: the force `sf * curve(t)` on `node`
/// along `axis`.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeLoad {
    pub node: u32,
    pub axis: usize,
    /// Index into `Model::curves`.
    pub curve: usize,
    pub sf: f64,
}

/// `*LOAD_SEGMENT` / `*LOAD_SEGMENT_SET`: the pressure `p = sf * curve(t)` (zero before the
/// birth time `at`) on a segment `N1 N2 N3 N4` (a triangle as `N1 N2 N3 N3`), a follower load:
/// a positive pressure pushes against the segment's normal by the right-hand rule
/// (LS-DYNA's convention), with the area vector of the current geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct PressureLoad {
    pub nodes: [u32; 4],
    /// Index into `Model::curves`.
    pub curve: usize,
    pub sf: f64,
    pub at: f64,
}

/// `*RIGIDWALL_PLANAR`: a fixed stonewall. The wall normal points from the tail (XT, YT, ZT)
/// towards the head (XH, YH, ZH) into the half-space where the nodes live.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidWall {
    /// Ordinal (1-based) of the wall in the deck, used in rwforc.csv.
    pub id: i64,
    /// Slave nodes; `None` (NSID = 0) means every node.
    pub nodes: Option<Vec<u32>>,
    pub tail: Vec3,
    pub head: Vec3,
    /// Coulomb friction coefficient; 1.0 or more means no sliding.
    pub fric: f64,
    /// `_FINITE`: the rectangle the wall covers; `None`: the whole plane.
    pub extent: Option<WallExtent>,
    /// The wall's body: the plane of `*RIGIDWALL_PLANAR` (and `*RIGIDWALL_GEOMETRIC_FLAT`),
    /// or a sphere or a cylinder (`*RIGIDWALL_GEOMETRIC_...`), which nodes stay out of.
    pub shape: WallShape,
    /// `_MOTION` of a geometric wall: its prescribed translation; `None`: fixed.
    pub motion: Option<WallMotion>,
}

/// The body of a rigid wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WallShape {
    /// The half-space behind the plane through the tail, normal tail -> head.
    Plane,
    /// A ball of radius `radius` about the tail.
    Sphere { radius: f64 },
    /// A solid cylinder of radius `radius` about the axis from the tail towards the head,
    /// from the tail over `length` along it (infinite: `f64::INFINITY`).
    Cylinder { radius: f64, length: f64 },
}

/// A geometric wall's prescribed translation along the unit vector `dir`: its displacement is
/// the curve (`displacement`, OPT 1) or the curve's integral from 0 (a velocity, OPT 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallMotion {
    /// Index into `Model::curves`.
    pub curve: usize,
    pub displacement: bool,
    pub dir: Vec3,
}

/// The rectangle of a `*RIGIDWALL_PLANAR_FINITE`: edges along the unit vectors l and
/// m = n x l from the tail, of lengths LENL and LENM. A node whose projection on the wall's
/// plane lies outside it is not stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallExtent {
    /// Unit edge vector l, in the wall's plane.
    pub l: Vec3,
    pub len_l: f64,
    pub len_m: f64,
}

impl RigidWall {
    /// The unit normal, from tail to head.
    pub fn normal(&self) -> Vec3 {
        let d = crate::math::sub(self.head, self.tail);
        crate::math::scale(d, 1.0 / crate::math::norm(d))
    }

    /// Whether the plane reaches a node at `x` (`tail` where the wall's tail is now):
    /// always for an unbounded wall; for a finite one, when `0 <= (x - tail).l <= LENL` and
    /// `0 <= (x - tail).m <= LENM`, m = n x l.
    pub fn covers(&self, x: Vec3, tail: Vec3, n: Vec3) -> bool {
        let Some(e) = self.extent else {
            return true;
        };
        let r = crate::math::sub(x, tail);
        let m = crate::math::cross(n, e.l);
        let (a, b) = (crate::math::dot(r, e.l), crate::math::dot(r, m));
        (0.0..=e.len_l).contains(&a) && (0.0..=e.len_m).contains(&b)
    }

    /// How far the wall's tail has moved by time `t` (`_MOTION`; zero for a fixed wall).
    pub fn offset(&self, curves: &[crate::curve::Curve], t: f64) -> Vec3 {
        match self.motion {
            None => [0.0; 3],
            Some(m) => {
                let c = &curves[m.curve];
                let d = if m.displacement {
                    c.eval(t)
                } else {
                    c.integral(t)
                };
                crate::math::scale(m.dir, d)
            }
        }
    }

    /// The gap of a node at `x` to the wall's surface, with the surface's outward unit normal
    /// there, the tail being at `tail` and `n` the wall's [`Self::normal`] (worked out once per
    /// step by the caller; negative gap: inside the wall's body); `None` where the
    /// wall does not reach (outside a finite plane's rectangle or past a finite cylinder's
    /// ends, or on a sphere's centre or a cylinder's axis).
    /// - plane: `g = (x - tail).n`;
    /// - sphere: `g = |x - tail| - R`, n along `x - tail`;
    /// - cylinder: with a the axis and `s = (x - tail).a`, `q = x - tail - s a`: `g = |q| - R`,
    ///   n along q.
    pub fn gap(&self, x: Vec3, tail: Vec3, n: Vec3) -> Option<(f64, Vec3)> {
        use crate::math::{dot, norm, scale, sub};
        let r = sub(x, tail);
        let radial = |q: Vec3, radius: f64| {
            let d = norm(q);
            (d > 0.0).then(|| (d - radius, scale(q, 1.0 / d)))
        };
        match self.shape {
            WallShape::Plane => self.covers(x, tail, n).then(|| (dot(r, n), n)),
            WallShape::Sphere { radius } => radial(r, radius),
            WallShape::Cylinder { radius, length } => {
                let s = dot(r, n);
                if !(0.0..=length).contains(&s) {
                    return None;
                }
                radial(sub(r, scale(n, s)), radius)
            }
        }
    }
}

/// Which side of a contact: by part set, part, segment set, or everything.
#[derive(Clone, Debug, PartialEq)]
pub enum ContactSurface {
    All,
    PartSet(usize),
    Part(usize),
    SegmentSet(usize),
}

/// `*CONTACT_TIED_SURFACE_TO_SURFACE` / `_NODES_TO_SURFACE`: the slave side's nodes follow
/// the master side's faces ([`crate::tied`]).
#[derive(Clone, Debug, PartialEq)]
pub struct TiedDef {
    /// Ordinal (1-based) of the contact among the deck's contacts.
    pub id: i64,
    pub slave: TiedSlave,
    pub master: ContactSurface,
}

/// The slave side of a tied contact: the nodes of a surface, or a node set (SSTYP 4).
#[derive(Clone, Debug, PartialEq)]
pub enum TiedSlave {
    Surface(ContactSurface),
    NodeSet(usize),
}

/// `*CONTACT_AUTOMATIC_SINGLE_SURFACE` / `*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE`.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactDef {
    /// Ordinal (1-based) of the contact in the deck, used in rcforc.csv.
    pub id: i64,
    pub single_surface: bool,
    /// `*CONTACT_AUTOMATIC_NODES_TO_SURFACE`: only the slave side's nodes are checked, against
    /// the master side's faces (surface to surface checks both ways).
    pub one_way: bool,
    pub slave: ContactSurface,
    /// Master side (surface to surface only).
    pub master: Option<ContactSurface>,
    /// Static and dynamic friction, exponential decay coefficient.
    pub fs: f64,
    pub fd: f64,
    pub dc: f64,
}

impl ContactDef {
    /// `*CONTACT_AUTOMATIC_SINGLE_SURFACE` over every part, the first contact of the deck, with
    /// static and dynamic friction `fs`, `fd` and no decay.
    pub fn single_surface_all(fs: f64, fd: f64) -> Self {
        Self {
            id: 1,
            single_surface: true,
            one_way: false,
            slave: ContactSurface::All,
            master: None,
            fs,
            fd,
            dc: 0.0,
        }
    }
}

/// `*MAT_ADD_SEPARATION`: the elements of `material` form a separation group.
#[derive(Clone, Debug, PartialEq)]
pub struct SeparationDef {
    /// Index into `Model::materials`.
    pub material: usize,
    /// 1: normal stress; 2: effective stress; 3: effective stress onset + Camacho-Ortiz
    /// linear law; 4: effective stress onset + Ortiz-Pandolfi exponential law.
    pub model: i32,
    /// The strength (Pa) of every interface, or the scale of the Weibull distribution.
    pub sigmax: f64,
    pub beta: f64,
    pub gc: f64,
    /// 1: faces to other materials may fail; 0: they stay bonded.
    pub bond: i32,
    /// How each interface's strength is drawn ([`crate::separation::strength`]).
    pub strength: StrengthDist,
}

/// The distribution of interface strengths in a separation group (`*MAT_ADD_SEPARATION`
/// DIST, SEED and card 2). Each interface draws once, from `seed` and its two elements' deck
/// ids ([`crate::separation::strength`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum StrengthDist {
    /// DIST 0: every interface has the strength SIGMAX.
    #[default]
    Constant,
    /// DIST 1: uniform between `smin` and `smax` (Pa).
    Uniform { smin: f64, smax: f64, seed: u64 },
    /// DIST 2: Weibull with scale SIGMAX, modulus `m` and threshold `smin`, for a face of
    /// area `aref` (`aref = 0`: no size scaling): the probability that a face of area A has
    /// failed at stress s is `1 - exp(-(A / aref) ((s - smin) / SIGMAX)^m)`.
    Weibull {
        m: f64,
        aref: f64,
        smin: f64,
        seed: u64,
    },
}

/// Hourglass control form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hourglass {
    /// IHQ = 1: viscous (Flanagan-Belytschko).
    Viscous,
    /// IHQ = 4 or 5: stiffness (Flanagan-Belytschko).
    Stiffness,
}

/// `*CONTROL_*` settings, with LS-DYNA's defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct Control {
    /// ENDTIM.
    pub end_time: f64,
    /// DTINIT (0: computed).
    pub dt_init: f64,
    /// TSSFAC, default 0.9.
    pub tssfac: f64,
    pub hourglass: Hourglass,
    /// QH, default 0.1.
    pub qh: f64,
    /// Quadratic bulk viscosity Q1, default 1.5.
    pub q1: f64,
    /// Linear bulk viscosity Q2, default 0.06.
    pub q2: f64,
    /// SLSFAC, default 0.1.
    pub slsfac: f64,
    /// PENOPT: the stiffness of a contact pair.
    pub penalty: PenaltyRule,
    /// DTMIN of `*CONTROL_TERMINATION`: the run stops (exit 3) when the time step falls below
    /// DTMIN times the first one. LS-DYNA's blank means no floor; cleave's default is
    /// [`DEFAULT_DTMIN`], so that a collapsing step ends the run instead of running for ever.
    pub dt_min: f64,
    /// LCTM of `*CONTROL_TIMESTEP` (index into `Model::curves`): the largest time step
    /// allowed, against time.
    pub dt_max_curve: Option<usize>,
}

/// The time step floor, as a fraction of the first step, when a deck gives no DTMIN: a step a
/// million times shorter than at the start means a run that would not end.
pub const DEFAULT_DTMIN: f64 = 1e-6;

/// `*CONTROL_CONTACT` PENOPT: which stiffness a node-to-face contact pair takes
/// ([`crate::contact::surface::FaceTable::pair_stiffness`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PenaltyRule {
    /// PENOPT = 0 or 1 (LS-DYNA's default): the smaller of the face's and the node's.
    #[default]
    Smaller,
    /// PENOPT = 2: the face's ("master segment stiffness").
    Face,
}

impl Default for Control {
    fn default() -> Self {
        Self {
            end_time: 0.0,
            dt_init: 0.0,
            tssfac: 0.9,
            hourglass: Hourglass::Viscous,
            qh: 0.1,
            q1: 1.5,
            q2: 0.06,
            slsfac: 0.1,
            penalty: PenaltyRule::Smaller,
            dt_min: DEFAULT_DTMIN,
            dt_max_curve: None,
        }
    }
}

/// `*DATABASE_*` requests. An interval of 0 means "not requested" for the CSV histories
/// (they are then written at the first and last time only) and "first and last state" for the
/// ParaView states.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OutputRequests {
    pub glstat_dt: f64,
    pub nodout_dt: f64,
    pub elout_dt: f64,
    pub rwforc_dt: f64,
    pub rcforc_dt: f64,
    pub d3plot_dt: f64,
    /// `*DATABASE_HISTORY_NODE` members, node indices.
    pub history_nodes: Vec<u32>,
    /// `*DATABASE_HISTORY_SOLID` members, element indices.
    pub history_solids: Vec<u32>,
}

impl Model {
    pub fn num_nodes(&self) -> usize {
        self.x0.len()
    }
    pub fn num_elements(&self) -> usize {
        self.conn.len()
    }
    /// The material of element `e`.
    pub fn element_material(&self, e: usize) -> &Material {
        &self.materials[self.parts[self.elem_part[e] as usize].material]
    }
}
