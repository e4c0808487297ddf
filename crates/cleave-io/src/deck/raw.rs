//! The deck as read, before references are resolved: deck ids, not indices, each item with
//! the line (and keyword) it came from so that the builder can name them in messages.

use std::rc::Rc;

use cleave_core::curve::Curve;
use cleave_core::material::Eos;
use cleave_core::math::Vec3;
use cleave_core::model::{Control, MaterialKind, OutputRequests, StrengthDist, Vad};

/// Where an item was read: keyword as written and 1-based line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Src {
    /// The file (the deck or one it includes).
    pub file: Rc<str>,
    pub keyword: Rc<str>,
    pub line: usize,
}

#[derive(Clone, Debug)]
pub struct RawNode {
    pub src: Src,
    pub id: i64,
    pub x: Vec3,
    /// Translational and rotational constraint codes TC, RC (0..7).
    pub tc: i32,
    pub rc: i32,
}

#[derive(Clone, Debug)]
pub struct RawElem {
    pub src: Src,
    pub id: i64,
    pub pid: i64,
    pub nodes: [i64; 8],
    /// Line of the card holding N1..N8 (the second card in the two-card form).
    pub node_line: usize,
}

#[derive(Clone, Debug)]
pub struct RawPart {
    pub src: Src,
    pub id: i64,
    pub title: String,
    pub secid: i64,
    pub mid: i64,
    /// EOSID, if given.
    pub eosid: Option<i64>,
    /// HGID (`*HOURGLASS`), if given.
    pub hgid: Option<i64>,
    /// `*PART_INERTIA`: the given mass properties and initial motion.
    pub inertia: Option<RawInertia>,
}

/// `*HOURGLASS`: `HGID IHQ QM IBQ Q1 Q2`; IHQ `None` when blank or 0 (the
/// `*CONTROL_HOURGLASS` form then).
#[derive(Clone, Debug)]
pub struct RawHourglass {
    pub src: Src,
    pub id: i64,
    pub ihq: Option<cleave_core::model::Hourglass>,
    pub qm: f64,
    pub q1: f64,
    pub q2: f64,
}

/// The inertia cards of `*PART_INERTIA` and `*CONSTRAINED_NODAL_RIGID_BODY_INERTIA`.
#[derive(Clone, Debug)]
pub struct RawInertia {
    /// XC, YC, ZC.
    pub centre: Vec3,
    /// TM.
    pub mass: f64,
    /// NODEID (NID): its coordinates are the centre instead.
    pub node: Option<i64>,
    /// The inertia tensor in global axes (turned from the local ones with IRCS 1).
    pub inertia: [[f64; 3]; 3],
    pub velocity: Vec3,
    pub omega: Vec3,
}

/// `*CONSTRAINED_NODAL_RIGID_BODY[_SPC][_INERTIA]`.
#[derive(Clone, Debug)]
pub struct RawNodalRigid {
    pub src: Src,
    pub id: i64,
    pub nsid: i64,
    pub cmo: i32,
    pub con1: i32,
    pub con2: i32,
    pub inertia: Option<RawInertia>,
}

/// `*CONSTRAINED_EXTRA_NODES_NODE` (`set` false) / `_SET`.
#[derive(Clone, Debug)]
pub struct RawExtraNodes {
    pub src: Src,
    pub pid: i64,
    pub id: i64,
    pub set: bool,
    pub iflag: bool,
}

#[derive(Clone, Debug)]
pub struct RawSection {
    pub src: Src,
    pub id: i64,
    pub elform: i32,
}

#[derive(Clone, Debug)]
pub struct RawMaterial {
    pub src: Src,
    pub id: i64,
    pub density: f64,
    pub young: f64,
    pub poisson: f64,
    pub kind: MaterialKind,
    /// `*MAT_JOHNSON_COOK` with G but neither PR nor E: the shear modulus, the bulk modulus to
    /// come from the part's equation of state (young and poisson are then NaN until it does).
    pub shear_only: Option<f64>,
}

/// `*EOS_LINEAR_POLYNOMIAL` or `*EOS_GRUNEISEN` (rho0 of the Gruneisen form is filled in from
/// the material it is attached to).
#[derive(Clone, Debug)]
pub struct RawEos {
    pub src: Src,
    pub id: i64,
    pub eos: Eos,
}

#[derive(Clone, Debug)]
pub struct RawSeparation {
    pub src: Src,
    pub mid: i64,
    pub model: i32,
    pub sigmax: f64,
    pub beta: f64,
    pub gc: f64,
    pub bond: i32,
    pub strength: StrengthDist,
}

/// A failure rule for material `mid`: FAIL / FS of its material card (`from_material`), or
/// a `*MAT_ADD_EROSION` card.
#[derive(Clone, Debug)]
pub struct RawErosion {
    pub src: Src,
    pub mid: i64,
    pub rule: cleave_core::erosion::ErosionRule,
    pub from_material: bool,
}

#[derive(Clone, Debug)]
pub struct RawCurve {
    pub src: Src,
    /// Scaled and offset, abscissae checked increasing.
    pub curve: Curve,
}

/// `*DEFINE_TABLE` / `*DEFINE_TABLE_2D`: values (scaled by SFA, offset by OFFA), each with its
/// line, and their curves.
#[derive(Clone, Debug)]
pub struct RawTable {
    pub src: Src,
    pub id: i64,
    pub values: Vec<(f64, usize)>,
    pub curves: TableCurves,
}

/// The curves of a table: the `*DEFINE_CURVE`s that follow it in the deck, one per value
/// (`*DEFINE_TABLE`; the index of the first in `RawDeck::curves`), or named (`_2D`).
#[derive(Clone, Debug)]
pub enum TableCurves {
    Following(usize),
    Ids(Vec<i64>),
}

/// A set: its id and its members (deck ids, or 4 node ids per segment), each with its line.
#[derive(Clone, Debug)]
pub struct RawSet<T> {
    pub src: Src,
    pub id: i64,
    pub members: Vec<(T, usize)>,
    /// `_GENERATE`: inclusive id ranges, each with its line; every defined id in them is a
    /// member.
    pub ranges: Vec<(i64, i64, usize)>,
    /// `*SET_NODE_GENERAL`: rules applied in order after the members and ranges.
    pub general: Vec<SetRule>,
}

/// One card of `*SET_NODE_GENERAL`: add (or, `delete`, take out) the nodes that `kind` and
/// `ids` name.
#[derive(Clone, Debug)]
pub struct SetRule {
    pub line: usize,
    pub delete: bool,
    pub kind: RuleKind,
    pub ids: Vec<i64>,
    /// The field (E1..E7) each id was read from, for messages.
    pub fields: Vec<u8>,
}

/// What a `*SET_NODE_GENERAL` rule's ids are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RuleKind {
    /// Every node (no ids).
    All,
    Node,
    Part,
    /// Node sets.
    Set,
}

/// What a boundary condition or initial velocity applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    Node(i64),
    NodeSet(i64),
    Part(i64),
    PartSet(i64),
    /// Every node of the model.
    All,
}

#[derive(Clone, Debug)]
pub struct RawSpc {
    pub src: Src,
    pub target: Target,
    pub dof: [bool; 6],
}

#[derive(Clone, Debug)]
pub struct RawMotion {
    pub src: Src,
    /// `Node`, `NodeSet` or `Part` (rigid).
    pub target: Target,
    pub window: cleave_core::model::Window,
    pub dof: RawDof,
    pub vad: Vad,
    pub lcid: i64,
    pub sf: f64,
}

/// A prescribed motion's DOF as written: a global axis, or a vector to look up.
#[derive(Clone, Copy, Debug)]
pub enum RawDof {
    /// DOF 1, 2, 3 (0, 1, 2).
    Axis(usize),
    /// DOF 5, 6, 7: rotation about global x, y, z (0, 1, 2).
    Rotation(usize),
    /// DOF 4, -4 (translation) or 8, -8 (`rotation`) along `*DEFINE_VECTOR` `vid`; `only` for
    /// the negative codes.
    Vector {
        vid: i64,
        only: bool,
        rotation: bool,
    },
}

/// `*DEFINE_VECTOR`: `VID XT YT ZT XH YH ZH CID`, the unit vector from tail to head.
#[derive(Clone, Debug)]
pub struct RawVector {
    pub src: Src,
    pub id: i64,
    /// Unit direction, in system `cid`'s axes (global without one).
    pub dir: Vec3,
    pub cid: Option<i64>,
}

/// `*INITIAL_VELOCITY_NODE` (omega 0) or `*INITIAL_VELOCITY_GENERATION`.
#[derive(Clone, Debug)]
pub struct RawInitVel {
    pub src: Src,
    pub target: Target,
    pub omega: f64,
    pub v: Vec3,
    pub centre: Vec3,
    pub axis: Vec3,
}

#[derive(Clone, Debug)]
pub struct RawBodyLoad {
    pub src: Src,
    pub axis: usize,
    pub lcid: Option<i64>,
    pub sf: f64,
}

/// `*LOAD_NODE_POINT` (a node) or `*LOAD_NODE_SET` (a node set).
#[derive(Clone, Debug)]
pub struct RawNodeLoad {
    pub src: Src,
    pub id: i64,
    pub set: bool,
    pub axis: usize,
    /// CID: the axis is the local system's (blank: global).
    pub cid: Option<i64>,
    pub lcid: i64,
    pub sf: f64,
}

/// `*LOAD_SEGMENT` (one segment's deck nodes) or `*LOAD_SEGMENT_SET` (a segment set).
#[derive(Clone, Debug)]
pub struct RawPressure {
    pub src: Src,
    pub segment: Option<[i64; 4]>,
    pub ssid: Option<i64>,
    pub lcid: i64,
    pub sf: f64,
    pub at: f64,
}

#[derive(Clone, Debug)]
pub struct RawWall {
    pub src: Src,
    pub nsid: Option<i64>,
    pub tail: Vec3,
    pub head: Vec3,
    pub fric: f64,
    pub extent: Option<cleave_core::model::WallExtent>,
    pub shape: cleave_core::model::WallShape,
    /// `_MOTION`: LCID, OPT 1 (a displacement), the unit direction.
    pub motion: Option<(i64, bool, Vec3)>,
}

/// A contact side: SSID/MSID with SSTYP/MSTYP (0 segment set, 2 part set, 3 part).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RawSurface {
    pub id: Option<i64>,
    pub typ: i32,
    pub field: &'static str,
}

#[derive(Clone, Debug)]
pub struct RawContact {
    pub src: Src,
    pub single_surface: bool,
    /// NODES_TO_SURFACE: the slave side's nodes against the master side's faces only.
    pub one_way: bool,
    /// `*CONTACT_TIED_...`: the slave nodes follow the master faces (a node-set slave, type 4,
    /// allowed).
    pub tied: bool,
    pub slave: RawSurface,
    pub master: Option<RawSurface>,
    pub fs: f64,
    pub fd: f64,
    pub dc: f64,
}

/// `*DEFINE_TRANSFORMATION`: its id and its rows `OPTION A1..A7` in order, each with its
/// line (the option upper case).
#[derive(Clone, Debug)]
pub struct RawTransform {
    pub src: Src,
    pub id: i64,
    pub ops: Vec<(String, [f64; 7], usize)>,
}

/// The id offsets of an `*INCLUDE_TRANSFORM` (IDNOFF IDEOFF IDPOFF IDMOFF IDSOFF IDFOFF
/// IDDOFF, IDROFF).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Offsets {
    /// IDNOFF: nodes.
    pub node: i64,
    /// IDEOFF: elements.
    pub elem: i64,
    /// IDPOFF: parts and nodal rigid bodies.
    pub part: i64,
    /// IDMOFF: materials and equations of state.
    pub mat: i64,
    /// IDSOFF: sets.
    pub set: i64,
    /// IDFOFF: curves.
    pub curve: i64,
    /// IDDOFF: other `*DEFINE_` ids. Coordinate systems are the only ones cleave reads, and a
    /// transformed include may not define them; the CID fields in one keep their ids (naming the
    /// main deck's systems).
    pub define: i64,
    /// IDROFF: every other id (sections, hourglass definitions).
    pub other: i64,
}

/// `*INCLUDE_TRANSFORM`: the group of blocks it read ([`super::lex::Block::group`]), its
/// offsets and TRANID.
#[derive(Clone, Debug)]
pub struct RawIncludeXform {
    pub src: Src,
    pub group: usize,
    pub offsets: Offsets,
    /// TRANID and the line it is on.
    pub tranid: Option<(i64, usize)>,
}

/// A local coordinate system (`*DEFINE_COORDINATE_...`): its axes as rows (local x, y, z in
/// global components), or why it has none cleave can use (one that follows nodes, `_NODES`;
/// one whose points span no plane): an error only where a field names it.
#[derive(Clone, Debug)]
pub struct RawFrame {
    pub src: Src,
    pub id: i64,
    pub axes: Result<[[f64; 3]; 3], &'static str>,
}

/// A CID field that cleave reads in global axes only: the system it names must have the
/// global axes (checked in the build).
#[derive(Clone, Debug)]
pub struct GlobalFrameUse {
    pub src: Src,
    pub field: &'static str,
    pub cid: i64,
}

/// Everything read from the deck.
#[derive(Clone, Debug, Default)]
pub struct RawDeck {
    pub title: String,
    /// `*HOURGLASS` definitions.
    pub hourglass: Vec<RawHourglass>,
    pub nodes: Vec<RawNode>,
    pub elems: Vec<RawElem>,
    pub parts: Vec<RawPart>,
    pub sections: Vec<RawSection>,
    pub materials: Vec<RawMaterial>,
    pub eos: Vec<RawEos>,
    pub separations: Vec<RawSeparation>,
    pub erosions: Vec<RawErosion>,
    pub tables: Vec<RawTable>,
    pub curves: Vec<RawCurve>,
    pub node_sets: Vec<RawSet<i64>>,
    pub part_sets: Vec<RawSet<i64>>,
    pub segment_sets: Vec<RawSet<[i64; 4]>>,
    pub solid_sets: Vec<RawSet<i64>>,
    pub nodal_rigid: Vec<RawNodalRigid>,
    pub extra_nodes: Vec<RawExtraNodes>,
    pub spcs: Vec<RawSpc>,
    pub motions: Vec<RawMotion>,
    /// `*DEFINE_VECTOR`s, in deck order.
    pub vectors: Vec<RawVector>,
    pub init_vel: Vec<RawInitVel>,
    pub body_loads: Vec<RawBodyLoad>,
    pub node_loads: Vec<RawNodeLoad>,
    /// `*DEFINE_COORDINATE_...` systems, and the fields that need theirs to be global.
    pub frames: Vec<RawFrame>,
    pub global_frames: Vec<GlobalFrameUse>,
    pub pressures: Vec<RawPressure>,
    pub walls: Vec<RawWall>,
    pub contacts: Vec<RawContact>,
    pub control: Control,
    /// LCTM of `*CONTROL_TIMESTEP` (a curve id) and where it was given.
    pub lctm: Option<(i64, Src)>,
    /// Where ENDTIM was set, if anywhere.
    pub termination: Option<Src>,
    pub output: OutputRequests,
    pub history_nodes: Vec<(i64, Src)>,
    pub history_solids: Vec<(i64, Src)>,
    /// `*DATABASE_HISTORY_SOLID_SET`: solid set ids.
    pub history_solid_sets: Vec<(i64, Src)>,
    /// `*DEFINE_TRANSFORMATION`s.
    pub transforms: Vec<RawTransform>,
    /// `*INCLUDE_TRANSFORM`s.
    pub include_xforms: Vec<RawIncludeXform>,
    pub warnings: Vec<String>,
}
