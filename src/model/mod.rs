//! Typed view of an OpenSim model document.
