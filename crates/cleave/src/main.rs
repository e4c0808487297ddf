//! `cleave`: explicit finite-element dynamics of solids with fracture by element separation.
//!
//! `main` only parses the command line, calls the command, and maps its error to the exit
//! codes of the interface page: 0 success, 2 bad input, 3 numerical failure, 130/143 stopped by SIGINT/SIGTERM (with a
//! restart file), 1 anything else.
//! It first fixes the allocator's large-block threshold ([`alloc_tuning`]).

mod alloc_tuning;
mod bench;
mod check;
mod cli;
mod crack_growth;
mod example;
mod failure;
mod fracture;
mod import;
mod interrupt;
mod progress;
mod restart;
mod results;
mod run;
mod run_status;

use clap::Parser;

use crate::failure::Failure;

fn main() {
    alloc_tuning::fix_mmap_threshold();
    let cli = cli::Cli::parse();
    let outcome = std::panic::catch_unwind(|| dispatch(cli));
    let code = match outcome {
        Ok(Ok(())) => 0,
        Ok(Err(f)) => {
            match f {
                Failure::Interrupted(..) => eprintln!("stopped: {f}"),
                _ => eprintln!("error: {f}"),
            }
            f.exit_code()
        }
        Err(_) => {
            eprintln!("error: internal error (a bug in cleave); please report it with the deck");
            1
        }
    };
    std::process::exit(code);
}

fn dispatch(cli: cli::Cli) -> Result<(), Failure> {
    match cli.command {
        cli::Command::Run(a) => run::run(&a),
        cli::Command::Check(a) => check::check(&a),
        cli::Command::Example(a) => example::example(&a),
        cli::Command::Import(a) => import::import(&a),
        cli::Command::Bench(a) => bench::bench(&a),
    }
}
