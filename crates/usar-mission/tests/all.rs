mod mission;
mod rescuer;
