mod rescue;
mod travel;
