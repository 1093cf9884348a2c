//! Kind `belt_3d` (issue 13, in progress): a closed belt of seed-003 co-rotational elements
//! over pulleys in space with crowned rims and flanges. Today only the model ([`model`]); the
//! scene tables, the declarations and the registry line are still to come.

pub mod model;
