mod mission;
mod rescuer;
mod runner;
