mod driver;
mod explore;
mod mcdm;
mod semantic;
mod team_size;
mod travel_time;
