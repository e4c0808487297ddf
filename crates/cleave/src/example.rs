//! `cleave example NAME`: write a ready deck for a bundled example.

use crate::cli::ExampleArgs;
use crate::failure::Failure;

pub fn example(_a: &ExampleArgs) -> Result<(), Failure> {
    Err(Failure::Input("no examples yet".into()))
}
