//! File formats: the lossless XML document under `.osim`/setup files, OpenSim tables
//! (`.sto`/`.mot`, `.trc`) and safe output. No numerics beyond parsing numbers.

pub mod atomic;
pub mod osim;
pub mod table;
pub mod xml;
