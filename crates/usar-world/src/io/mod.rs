//! Importers and exporters for maps made elsewhere: ROS `map_server` (YAML + PGM/PNG), bare
//! PGM/PNG images, MovingAI `.map` grids and `.scen` scenario files; rotated ROS maps turned
//! onto the axis-aligned grid; `source`: a scene named as a user names one (file or generator).

pub mod image_map;
pub mod movingai;
pub mod ros;
pub mod rotation;
pub mod source;
