def run_many(): pass
