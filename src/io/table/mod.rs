//! Tables: OpenSim `.sto`/`.mot` storage files and `.trc` marker trajectories.
