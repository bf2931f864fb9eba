// demo: being written
