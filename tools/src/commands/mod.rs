//! One module per subcommand.

pub(crate) mod accuracy;
pub(crate) mod bench;
pub(crate) mod compare;
pub(crate) mod counters;
pub(crate) mod geometry;
pub(crate) mod points;
pub(crate) mod probe;
pub(crate) mod render;
pub(crate) mod sun_hours;
