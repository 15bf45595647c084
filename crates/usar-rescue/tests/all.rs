mod controller;
mod exploration;
mod rescue;
mod travel;
