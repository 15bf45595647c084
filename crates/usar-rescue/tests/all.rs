mod rescue;
