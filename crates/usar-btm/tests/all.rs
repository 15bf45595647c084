mod build;
mod store;
