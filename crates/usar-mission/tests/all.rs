mod mission;
