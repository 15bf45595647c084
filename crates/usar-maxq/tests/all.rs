mod apprentice;
mod stepper;
mod taxi;
