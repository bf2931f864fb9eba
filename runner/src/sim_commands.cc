// sim commands: being written
