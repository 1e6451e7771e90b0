//! Runs other opacity-micromap bakers on one texture and a list of UV
//! triangles, and writes their output in the Vulkan layout, so that
//! `micromap-index verify-bake` can check it. See README.md.

pub mod bakers;
pub mod input;
pub mod output;
