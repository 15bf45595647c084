mod driver;
mod explore;
mod ground_truth;
mod mcdm;
mod semantic;
mod team_size;
mod travel_time;
