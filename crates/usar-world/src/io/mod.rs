//! Importers and exporters for maps made elsewhere: ROS `map_server` (YAML + PGM/PNG), bare
//! PGM/PNG images, MovingAI `.map` grids and `.scen` scenario files; rotated ROS maps turned
//! onto the axis-aligned grid.

pub mod image_map;
pub mod movingai;
pub mod ros;
pub mod rotation;
