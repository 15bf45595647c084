mod explore;
mod mcdm;
mod team_size;
