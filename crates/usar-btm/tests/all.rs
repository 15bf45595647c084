mod plan;
mod store;
