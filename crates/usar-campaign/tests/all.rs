mod engine;
mod folders;
mod stats;
