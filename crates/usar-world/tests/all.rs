//! Integration tests of usar-world, one binary (see STYLE.md).

mod cellview;
mod generate_building;
mod generate_course_rubble;
mod io_movingai;
mod io_ros;
mod render;
mod scene_file;
