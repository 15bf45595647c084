mod apprentice;
mod taxi;
