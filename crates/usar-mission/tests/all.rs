mod live;
mod mission;
mod rescuer;
mod runner;
