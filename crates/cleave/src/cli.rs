//! Command-line definitions (see `shared/spec/interface.md`).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "cleave",
    version,
    about = "Explicit finite-element dynamics of solids with fracture by element separation"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run a keyword deck.
    Run(RunArgs),
    /// Read and validate a deck without running it; print a model summary.
    Check(CheckArgs),
    /// Write a ready deck for a bundled example.
    Example(ExampleArgs),
    /// Convert a Gmsh mesh (.msh) to keyword text: nodes, solids, sets.
    Import(ImportArgs),
    /// Benchmarks (time per element step, peak memory).
    Bench(BenchArgs),
}

#[derive(Args, Debug)]
pub struct RunArgs {
    /// The keyword deck (.k).
    pub deck: PathBuf,
    /// Output folder (default: DECK.out beside the deck).
    #[arg(short = 'o', long = "output")]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Override ENDTIM of the deck.
    #[arg(long = "end-time")]
    pub end_time: Option<f64>,
    /// Ignore every *MAT_ADD_SEPARATION (same mesh, no split nodes).
    #[arg(long = "no-separation")]
    pub no_separation: bool,
    /// No progress bar.
    #[arg(long, short = 'q')]
    pub quiet: bool,
    /// Run the step on a GPU (wgpu: Vulkan, Metal or DX12, with 64-bit float shaders). A deck
    /// that asks for a feature the GPU step does not have yet is refused with its name (exit 2).
    #[arg(long)]
    pub gpu: bool,
    /// Write a restart file (OUTDIR/restart.ckpt) every T of simulated time; one is also
    /// written when SIGINT or SIGTERM stops the run.
    #[arg(long = "checkpoint-every", value_name = "T")]
    pub checkpoint_every: Option<f64>,
    /// Continue the run from a restart file of this deck (the histories in OUTDIR are cut
    /// back to where the file was written and go on from there).
    #[arg(long, value_name = "FILE")]
    pub restart: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// The keyword deck (.k).
    pub deck: PathBuf,
}

#[derive(Args, Debug)]
pub struct ImportArgs {
    /// The Gmsh mesh (MSH 4.1 or 2.2, ASCII or binary).
    pub mesh: PathBuf,
    /// Where to write the keyword text (default: MESH.k beside the mesh).
    #[arg(short = 'o', long = "output")]
    pub out: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct ExampleArgs {
    /// Example name (`cleave example --list` lists them).
    pub name: Option<String>,
    /// Where to write the deck (default: NAME.k in the current folder).
    #[arg(short = 'o', long = "output")]
    pub out: Option<PathBuf>,
    /// List the examples.
    #[arg(long)]
    pub list: bool,
    /// Override the end time.
    #[arg(long = "end-time")]
    pub end_time: Option<f64>,
    /// Mesh size, where the example has several (ball-impact: 256, 425, 648, 2800, 8775,
    /// 20000, 160000 or 1097440 elements in the ball; fragmenting-bar: any number of elements along the bar,
    /// 20 per characteristic length).
    #[arg(long)]
    pub elements: Option<usize>,
    /// Separation model of the crack path (three-point-bend: 1, the paper's normal-stress
    /// criterion, 3, a linear cohesive law, or 4, an exponential one).
    #[arg(long)]
    pub model: Option<i32>,
    /// Draw every interface's strength from a Weibull distribution of this modulus, with the
    /// example's strength as its scale (`*MAT_ADD_SEPARATION` DIST 2, no size scaling).
    #[arg(long)]
    pub weibull: Option<f64>,
    /// Seed of the strength draw (with --weibull, and fragmenting-bar's uniform strengths).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// fragmenting-bar: the strain rate in units of eps_dot0 = c SIGMAX^3 / (E^2 GC)
    /// (default 1).
    #[arg(long = "strain-rate")]
    pub strain_rate: Option<f64>,
    /// fragmenting-bar: half-width of the uniform strength distribution, a fraction of the
    /// mean strength (default 0.1).
    #[arg(long)]
    pub spread: Option<f64>,
    /// Write the deck without its separation card.
    #[arg(long = "no-separation")]
    pub no_separation: bool,
    /// Erode instead of separating: each separation group becomes `*MAT_ADD_EROSION` with
    /// SIGP1 = its strength, so an element is deleted when its largest principal stress
    /// reaches the stress at which its faces would have failed (the paper's comparison).
    #[arg(long)]
    pub erosion: bool,
    /// taylor-bar: the element shape, `hex` (default), `hex2` (the hexahedra with ELFORM 2),
    /// `wedge`, `tet` or `tet13` (each hexahedron of the same mesh cut into 2 wedges or 6
    /// tetrahedra; the tetrahedra with ELFORM 10, or 13: nodal pressure averaging).
    #[arg(long)]
    pub shape: Option<String>,
}

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// What to measure: `cube` (an elastic block), `ball` (the ceramic ball on a rigid plate
    /// of `cleave example ball-impact`, with contact), `paper-tables` (the paper's Tables II
    /// and III: every ball mesh with and without fracture, the short runs repeated in pairs and
    /// the median shown) or `fragmentation` (the fragmenting bar over a range of strain rates
    /// against Zhou, Molinari and Ramesh's fit and Grady's estimate).
    pub what: String,
    /// Number of elements: for a cube the nearest n^3 (default 100000); for the ball one of
    /// the example's meshes (default 2800).
    #[arg(long)]
    pub elements: Option<usize>,
    /// Time steps to run.
    #[arg(long, default_value_t = 200)]
    pub steps: u64,
    /// Worker threads.
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Cube and ball: run the step on a GPU (as `cleave run --gpu`): the cube with
    /// `--separation` its element separation too, the ball breaking on its plate (or unbroken
    /// with `--no-separation`). paper-tables and fragmentation are CPU benchmarks: with --gpu
    /// they are refused (exit 2), not run on the CPU.
    #[arg(long)]
    pub gpu: bool,
    /// Ball with --gpu: time every pass of every step of the run with the device's timestamps
    /// (the steps that halt for the host and the rest of such a step included) and print each
    /// pass's share. Each pass then runs in a compute pass of its own, so the run is slower
    /// than without.
    #[arg(long)]
    pub passes: bool,
    /// Cube: put every element in a separation group (MODEL 1, a strength nothing reaches), so
    /// the step carries the split nodes, their coincident sets and the failure check of every
    /// interface.
    #[arg(long)]
    pub separation: bool,
    /// Ball: simulated time to run (default 50 us: the impact and the first fractures).
    #[arg(long = "end-time")]
    pub end_time: Option<f64>,
    /// Ball: drop the separation card (no fracture).
    #[arg(long = "no-separation")]
    pub no_separation: bool,
    /// Ball: print the measurements as one JSON line (what `paper-tables` reads).
    #[arg(long)]
    pub json: bool,
    /// paper-tables: directory for paper-tables.md and paper-tables.csv (default
    /// paper-tables); fragmentation: for fragmentation.md, .csv and .png (default
    /// fragmentation).
    #[arg(short = 'o', long = "output")]
    pub output: Option<std::path::PathBuf>,
    /// fragmentation: the strain rates, in units of eps_dot0, comma-separated (default
    /// 0.1,0.3,1,3,10,30).
    #[arg(long)]
    pub rates: Option<String>,
    /// fragmentation: runs per strain rate, with seeds 1 to K.
    #[arg(long, default_value_t = 3)]
    pub seeds: u64,
    /// fragmentation: half-width of the uniform strength distribution, a fraction of the mean
    /// strength (default 0.1).
    #[arg(long)]
    pub spread: Option<f64>,
    /// fragmentation: the time step scale factor TSSFAC (default 0.2: the fragment count has
    /// converged with the time step there).
    #[arg(long)]
    pub tssfac: Option<f64>,
}
