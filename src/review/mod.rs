//! Semantic comparison of OpenSim documents for review.
