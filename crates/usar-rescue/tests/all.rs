mod exploration;
mod rescue;
mod travel;
