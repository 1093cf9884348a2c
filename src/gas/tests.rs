//! Tests of the gas component, one quantity at a time.
