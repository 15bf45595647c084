//! Integration tests of usar-map, one binary (see STYLE.md).

mod frontier;
mod planning;
mod segmentation;
