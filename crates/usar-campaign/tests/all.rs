mod engine;
mod stats;
