//! Forward-mode dual numbers with a fixed number of derivative directions.
