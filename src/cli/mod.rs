//! Command-line interface: the only module that prints.
