//! Support for `tests/hostile_input.rs`: running `verity` on hostile input as a separate
//! process with a timeout and memory caps ([`process`]), judging its answer ([`judge`]),
//! seeded mutations ([`rng`], [`mutate`], with the EXR and glTF specifics in [`exr`] and
//! [`gltf`]), the mutation families ([`family`]) and the checked-in reproducers
//! ([`corpus`], manifest in `tests/hostile/manifest.rs`).

pub mod corpus;
pub mod exr;
pub mod family;
pub mod gltf;
pub mod judge;
pub mod mutate;
pub mod process;
pub mod rng;
