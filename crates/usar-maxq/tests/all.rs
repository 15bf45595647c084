mod taxi;
