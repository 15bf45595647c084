mod explore;
mod mcdm;
