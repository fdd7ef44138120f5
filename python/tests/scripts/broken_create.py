def createScene(rootNode):
    rootNode.addChild("body")
    return 1 / 0
