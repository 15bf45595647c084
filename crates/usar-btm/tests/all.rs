mod build;
mod plan;
mod store;
mod validate;
