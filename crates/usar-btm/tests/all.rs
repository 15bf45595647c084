mod build;
mod plan;
mod store;
