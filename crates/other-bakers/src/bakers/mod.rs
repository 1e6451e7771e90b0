//! The bakers this tool can run, each converted to [`Micromaps`](crate::output::Micromaps):
//! the registry ([`all`], [`by_name`]); what a baker is lives in `baker.rs`.

mod baker;
pub mod exact;
mod meshopt_common;
pub mod meshopt_cpp;
pub mod meshopt_rs;
pub mod omm_sdk;

pub use baker::{Baked, Baker, Conventions, Request, SamplerRequest};
pub use meshopt_common::meshopt_sample;

/// Every baker compiled into this build.
pub fn all() -> Vec<Box<dyn Baker>> {
    vec![
        Box::new(meshopt_cpp::MeshoptCpp),
        Box::new(meshopt_rs::MeshoptRs),
        Box::new(exact::MicromapIndex),
        Box::new(omm_sdk::OmmSdk),
    ]
}

/// The baker named `name`.
pub fn by_name(name: &str) -> Option<Box<dyn Baker>> {
    all().into_iter().find(|b| b.name() == name)
}

#[cfg(test)]
mod tests;
